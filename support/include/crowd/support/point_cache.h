// Point caches: one garment's vertex positions per frame, fixed topology, as written by DCC
// tools' cloth solvers. Two formats:
//   PC2 (little-endian): "POINTCACHE2\0", int32 version 1, int32 vertices, float start frame,
//       float sample step (scene frames per sample), int32 frames; then frames x vertices x
//       3 floats. It stores no frame rate: the caller gives one (--fps).
//   MDD (big-endian): int32 frames, int32 vertices, frames float times in seconds; then
//       frames x vertices x 3 floats. Its frame rate is 1 / (time step), which must be uniform.
// The reader streams: it checks the header against the file's size (a header that lies about
// its counts, or a truncated file, is an error before any frame is read), then reads any range
// of vertices of any frame on demand, so a 180 MB cache is never held whole. Every value read
// is checked finite; an error names the file, frame and vertex.
#pragma once
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/file_read.h"

namespace crowd {

enum class PointCacheFormat { Pc2, Mdd };

struct PointCacheInfo {
  PointCacheFormat format = PointCacheFormat::Pc2;
  uint32_t vertexCount = 0;
  uint32_t frameCount = 0;
  double fps = 0.0;        // from the file (MDD); 0 where the file stores none (PC2)
  double startFrame = 0.0; // PC2's start frame; MDD: first time x fps
  uint64_t dataOffset = 0; // byte offset of frame 0
};

class PointCacheReader {
public:
  // Opens and checks `path` (a regular file within `bound`; ".pc2" or ".mdd", else by its
  // magic).
  PointCacheReader(const std::string &path, const FileBound &bound = {});
  const PointCacheInfo &info() const { return info_; }
  const std::string &path() const { return path_; }
  // Positions of vertices [first, first + count) at `frame` into out (resized to count).
  void read(uint32_t frame, uint32_t first, uint32_t count, std::vector<glm::vec3> &out);
  void readFrame(uint32_t frame, std::vector<glm::vec3> &out) {
    read(frame, 0, info_.vertexCount, out);
  }

private:
  std::string path_;
  PointCacheInfo info_;
  std::ifstream in_;
  std::vector<uint8_t> raw_;
};

// The bytes of a cache in `format`: frames[f][v]; every frame has the same vertex count.
// `fps` sets MDD's times (PC2 has no field for it); `pc2Start` and `pc2Step` are PC2's start
// frame and sample step (crowdbake pose writes seconds there).
std::vector<uint8_t> encodePointCache(PointCacheFormat format,
                                      const std::vector<std::vector<glm::vec3>> &frames, double fps,
                                      float pc2Start = 0.0f, float pc2Step = 1.0f);

} // namespace crowd
