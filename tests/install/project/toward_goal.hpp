#pragma once
// A controller of one's own: turns toward the goal and drives at it.

#include "barn/controllers/controller.hpp"

class TowardGoal : public barn::controllers::Controller {
 public:
  void reset(const barn::controllers::EpisodeInfo& info) override;
  barn::core::Twist act(const barn::controllers::Observation& observation) override;
  double period() const override { return 0.05; }  // [s] 20 Hz

 private:
  barn::controllers::EpisodeInfo info_;
};
