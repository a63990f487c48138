#include "barn/viz/plots.hpp"

#include <gtest/gtest.h>

TEST(Placeholder, Builds) {}
