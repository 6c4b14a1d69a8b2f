// The table of image functions the crowd_oiio module hands to images.cpp (same compiler, same
// standard library: both are built by this project). Errors come back as text, not exceptions.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "crowd/formats/registry.h"

namespace crowd::images {

struct Codec {
  bool (*decode)(const std::vector<uint8_t> &bytes, const std::string &name, int maxSide,
                 pack::Image &out, std::string &why);
  bool (*write)(const std::string &path, const pack::Image &image, std::string &why);
  bool (*encodePng)(const pack::Image &image, std::vector<uint8_t> &out, std::string &why);
};

} // namespace crowd::images

// The module's one entry point.
extern "C" const crowd::images::Codec *crowd_image_codec();
inline constexpr const char *kImageModule = "crowd_oiio.so";
