// RGTC2 (BC5) blocks, which OpenGL samples natively (GL_COMPRESSED_RG_RGTC2, core since 3.0):
// two channels per 4x4 texels in 16 bytes, each channel as two 8-bit endpoints and a 3-bit index
// per texel into the levels between them (the red block, then the green one). The impostor atlases
// keep their normals (octahedral) and UVs in it: a byte per texel instead of 8 or 16.
// Written here, not taken from Debian's libsquish: formats/ depends on the standard library only,
// squish takes 8-bit input (a second quantisation of the float normals) and fits every texel of a
// block, where an impostor block must fit its covered texels only (the others are discarded).
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace crowd::pack {

inline constexpr size_t kBc5BlockBytes = 16;

// Bytes of a width x height image (whole blocks; a partial block at an edge is a whole one).
size_t bc5Bytes(uint32_t width, uint32_t height);

// Encodes `rg` (two values in 0..1 per texel, row-major, width x height). Only texels with
// used[i] != 0 are fitted (the others decode to whatever their block gives); a block with none
// is all zero. Deterministic: the same input gives the same bytes on every machine.
std::vector<uint8_t> encodeBc5(const float *rg, const uint8_t *used, uint32_t width,
                               uint32_t height);

// Decodes bc5Bytes(width, height) bytes into two values in 0..1 per texel, as the RGTC
// specification's decoder does (levels computed in floating point from the 8-bit endpoints).
void decodeBc5(const uint8_t *blocks, uint32_t width, uint32_t height, float *rg);

} // namespace crowd::pack
