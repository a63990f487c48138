#pragma once
/// The file formats every figure is written in, chosen by the output file's extension, so a
/// command can refuse a bad `-o` before it does any work.

#include <filesystem>

namespace barn::viz {

/// .png: an ARGB image, 1 px per layout unit. .pdf, .svg: vector pages, 1 pt per layout unit
/// (so a figure documented as W x H px is a W x H pt page). The extension's case is ignored.
enum class ImageFormat { Png, Pdf, Svg };

/// The format of `path`; core::InputError "<path>: unknown image type '<ext>' (expected .png,
/// .pdf or .svg)" for any other extension, or none.
ImageFormat imageFormatFor(const std::filesystem::path& path);

}  // namespace barn::viz
