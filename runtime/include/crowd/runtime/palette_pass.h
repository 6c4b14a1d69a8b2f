// The palette pass on the GPU (shaders/palette.comp): a pack's joint tracks uploaded once; each
// frame the palette requests of the instances drawn, equal ones shared, decoded into the
// palettes the vertex shader skins from (bindings 9 and 10 of shaders/crowd.vert). Needs a
// current GL 4.5 context.
#pragma once
#include <cstdint>
#include <vector>

#include "crowd/formats/chunks.h"
#include "crowd/runtime/track_palettes.h"

namespace crowd::runtime {

class PalettePass {
public:
  // Throws crowd::Error when the pack has no joint tracks. `slot`: paletteSlots'.
  PalettePass(const pack::AnimationPack &p, uint32_t instances, float slot = kClipSampleSlot);
  ~PalettePass();
  PalettePass(const PalettePass &) = delete;
  PalettePass &operator=(const PalettePass &) = delete;

  // Decodes a palette for each distinct request of instances `ids`, whose params and fade sit
  // at `instanceData[i * stride + 12]` (clip, time offset, speed, palette; fade: 4 more), at
  // scene time `seconds`, with `program` (shaders/palette.comp); returns the palettes decoded.
  // `timed`: GPU timestamps around the dispatch, read back by gpuMilliseconds (which waits).
  uint32_t run(unsigned program, const std::vector<float> &instanceData, size_t stride,
               const std::vector<uint32_t> &ids, float seconds, bool timed = false);
  double gpuMilliseconds() const;
  void bind() const; // the palettes and each instance's palette: bindings 9 and 10
  uint32_t joints() const { return joints_; }
  int32_t paletteOf(uint32_t instance) const { return paletteOf_[instance]; }
  const std::vector<float> &slots() const { return slots_; } // per clip: paletteSlots'

private:
  const pack::AnimationPack *pack_;
  std::vector<float> slots_;
  uint32_t nodes_ = 0, joints_ = 0, clips_ = 0, capacity_ = 0;
  unsigned buffers_[8] = {}; // rig, tracks, times, stream, requests, palettes, globals, paletteOf
  unsigned queries_[2] = {}; // timestamps before and after the last timed dispatch
  bool timed_ = false;
  std::vector<int32_t> paletteOf_;
  std::vector<PaletteRequest> requests_;
};

} // namespace crowd::runtime
