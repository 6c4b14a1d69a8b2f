#include "crowd/runtime/clip_switch.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace crowd::runtime {
namespace {

// A uniform number in [0, 1) from (seed, instance, segment, stream): splitmix64 over the words,
// so any segment of any instance is drawn without drawing the ones before it.
double uniform(uint64_t seed, uint64_t instance, uint64_t segment, uint64_t stream) {
  uint64_t x = seed;
  for (uint64_t word : {instance, segment, stream}) {
    x += 0x9e3779b97f4a7c15ull ^ word;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    x ^= x >> 31;
  }
  return double(x >> 11) * 0x1.0p-53;
}

} // namespace

float ClipState::weightAt(double seconds) const {
  if (from < 0 || fadeSeconds <= 0)
    return 1.0f;
  return std::clamp(float(seconds - fadeStart) / float(fadeSeconds), 0.0f, 1.0f);
}

ClipSchedule::ClipSchedule(const Scene &scene) : scene_(scene), cursors_(scene.instances.size()) {
  for (size_t i = 0; i < cursors_.size(); ++i) {
    reset(i);
    dynamic_ = dynamic_ || cursors_[i].state.from >= 0;
  }
  dynamic_ = dynamic_ || scene.switching.enabled();
}

void ClipSchedule::reset(size_t i) {
  const Instance &inst = scene_.instances[i];
  const ClipSwitching &sw = scene_.switching;
  Cursor &c = cursors_[i];
  c.segment = 0;
  c.start = -std::numeric_limits<double>::infinity();
  c.end = sw.enabled() ? sw.maxEvery * uniform(sw.seed, i, 0, 0)
                       : std::numeric_limits<double>::infinity();
  c.state = {inst.clip,       inst.timeOffset,  inst.fade.from, inst.fade.fromOffset,
             inst.fade.start, inst.fade.seconds};
}

void ClipSchedule::advance(size_t i) {
  const ClipSwitching &sw = scene_.switching;
  Cursor &c = cursors_[i];
  ++c.segment;
  c.start = c.end;
  c.end = c.start + sw.minEvery + (sw.maxEvery - sw.minEvery) * uniform(sw.seed, i, c.segment, 0);
  // The next clip by weight among the others; with no other, the instance keeps its clip.
  std::vector<double> w = sw.weights;
  w.resize(scene_.clipNames.size(), 0.0);
  w[c.state.clip] = 0;
  double total = 0;
  for (double x : w)
    total += x;
  if (total <= 0)
    return;
  double pick = total * uniform(sw.seed, i, c.segment, 1);
  uint32_t next = 0;
  while (next + 1 < w.size() && (pick >= w[next] || w[next] == 0))
    pick -= w[next++];
  while (w[next] == 0) // rounding ran past the last clip with a weight
    --next;
  const double speed = scene_.instances[i].speed;
  c.state = {next,
             -c.start * speed, // the new clip starts at its beginning
             int32_t(c.state.clip),
             c.state.offset,
             c.start,
             sw.fade};
}

const ClipState &ClipSchedule::at(size_t i, double seconds) {
  Cursor &c = cursors_[i];
  if (seconds < c.start)
    reset(i);
  while (seconds >= c.end)
    advance(i);
  return c.state;
}

} // namespace crowd::runtime
