// A PNG's container checked before OpenImageIO decodes it. Debian's OpenImageIO 2.4 leaves
// libpng's own error handler in place, which prints "libpng error: ..." on stderr for a bad
// header, a cut file or corrupt data, beside the error OpenImageIO returns: a bake's one clear
// line became three. What libpng would reject is turned away here first, with one reason.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace crowd::images {

// True where `bytes` start with the PNG signature.
bool isPng(const std::vector<uint8_t> &bytes);

// False, with `why`, unless the PNG's chunks are whole with right CRCs, its IHDR valid (each
// side 1..maxSide), a PLTE precedes the data where the colour type needs one, an IEND ends it,
// and its IDAT data inflates to exactly the rows its header promises.
bool pngIsWhole(const std::vector<uint8_t> &bytes, int maxSide, std::string &why);

} // namespace crowd::images
