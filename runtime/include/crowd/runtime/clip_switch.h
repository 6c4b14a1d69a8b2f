// Clip changes over time: what each instance of a scene plays at a time, and the clip it is
// crossfading from. A scene's "switch" makes every instance change clip after a seeded random
// interval, to another of the scene's clips drawn by weight; an instance can also start in a
// fade (a preview's clip key). The player and the CPU reference read the same schedule.
#pragma once
#include <cstdint>
#include <vector>

#include "crowd/runtime/scene.h"

namespace crowd::runtime {

// What an instance plays: `clip` at `seconds * speed + offset`, and while fading, `from` at
// `seconds * speed + fromOffset`. Clips index the scene's clip names.
struct ClipState {
  uint32_t clip = 0;
  double offset = 0;
  int32_t from = -1; // -1: no fade
  double fromOffset = 0, fadeStart = 0, fadeSeconds = 0;
  // The share of `clip`: 0 at fadeStart, 1 from fadeStart + fadeSeconds on (and without a fade).
  // The shader computes the same in single precision.
  float weightAt(double seconds) const;
};

class ClipSchedule {
public:
  explicit ClipSchedule(const Scene &scene);
  // True when some instance's state changes with time (a switch or a fade).
  bool dynamic() const { return dynamic_; }
  // The state of scene instance `i` at `seconds`. Cheapest for times that move forward.
  const ClipState &at(size_t i, double seconds);

private:
  struct Cursor {
    uint32_t segment = 0; // switches so far
    double start = 0, end = 0;
    ClipState state;
  };
  void reset(size_t i);
  void advance(size_t i);
  const Scene &scene_;
  std::vector<Cursor> cursors_;
  bool dynamic_ = false;
};

} // namespace crowd::runtime
