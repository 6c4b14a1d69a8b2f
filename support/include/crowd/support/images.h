// Image files, through OpenImageIO loaded on first use. OpenImageIO brings some 260 shared
// libraries (video, DICOM, GDAL, OpenVDB...): loading them took 0.45 s of every crowdbake
// start (a program linking only OpenImageIO starts in 0.45 s here, crowdbake's other libraries
// in 0.02 s), though inspect, verify, diff, pose, report and untextured bakes read no image.
// So the OpenImageIO calls live in a module (crowd_oiio.so, beside the program) that the first
// image opens, for crowdbake and crowdplay alike; only tests include OpenImageIO themselves. The
// module holds no CGAL: runtime/ stays MIT.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "crowd/formats/registry.h"

namespace crowd::images {

// Decodes `bytes` (PNG, JPEG, WebP...: the format by `name`'s extension) into its channels as
// stored, 8 bits each. An image wider or taller than maxSide is not decoded. False, with `why`,
// when it cannot be decoded, the module's failure to load included.
bool decode(const std::vector<uint8_t> &bytes, const std::string &name, int maxSide,
            pack::Image &out, std::string &why);

// Writes the image to `path`, the format by its extension (zip compression where the format
// has it, as EXR does). Throws Error.
void write(const std::string &path, const pack::Image &image);

// The image as PNG bytes. Throws Error.
std::vector<uint8_t> encodePng(const pack::Image &image);

} // namespace crowd::images
