// The CLIP chunk: the clip table.
#include "crowd/formats/chunks.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "chunk_checks.h"
#include "crowd/formats/bytes.h"
#include "crowd/formats/error.h"

namespace crowd::pack {

using namespace checks;

std::vector<uint8_t> encode(const std::vector<Clip> &clips) {
  ByteWriter w;
  w.put<uint32_t>(uint32_t(clips.size()));
  for (const auto &c : clips) {
    w.putString(c.name);
    w.put<float>(c.fps);
    w.put<float>(c.startTime);
    w.put<uint32_t>(c.firstFrame);
    w.put<uint32_t>(c.frameCount);
    w.put<uint8_t>(c.loop ? 1 : 0);
  }
  return w.take();
}

std::vector<Clip> decodeClips(std::span<const uint8_t> bytes, const std::string &context) {
  ByteReader r(bytes, context);
  uint32_t n = r.get<uint32_t>("clip count");
  if (n > 100000)
    r.fail("clip count", std::to_string(n) + " is absurd");
  std::vector<Clip> clips;
  for (uint32_t i = 0; i < n; ++i) {
    Clip c;
    c.name = r.getString("clip name");
    c.fps = r.get<float>("fps");
    c.startTime = r.get<float>("start time");
    c.firstFrame = r.get<uint32_t>("first frame");
    c.frameCount = r.get<uint32_t>("frame count");
    uint8_t loop = r.get<uint8_t>("loop");
    if (loop > 1)
      r.fail("loop", "flag is " + std::to_string(loop));
    c.loop = loop == 1;
    if (!(std::isfinite(c.fps) && c.fps > 0 && c.fps <= 10000))
      r.fail("fps", "clip '" + c.name + "' has fps " + std::to_string(c.fps));
    if (!std::isfinite(c.startTime))
      r.fail("start time", "not finite");
    if (c.frameCount == 0)
      r.fail("frame count", "clip '" + c.name + "' has no frames");
    clips.push_back(c);
  }
  r.expectEnd();
  return clips;
}

} // namespace crowd::pack
