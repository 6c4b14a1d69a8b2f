#include "crowd/runtime/agents.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"

namespace crowd::runtime {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;
constexpr size_t kNowhere = std::numeric_limits<size_t>::max();

uint64_t mix(uint64_t x) { // splitmix64's finaliser
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

float wrapAngle(float a) {
  a = std::fmod(a + kPi, 2 * kPi);
  return (a < 0 ? a + 2 * kPi : a) - kPi;
}

glm::vec2 direction(float heading) { return {std::sin(heading), std::cos(heading)}; }

// cos and sin of k * 30 degrees, k = 1..6: the courses an agent tries around an obstacle.
const glm::vec2 kTurns[6] = {{0.8660254f, 0.5f},  {0.5f, 0.8660254f},  {0.0f, 1.0f},
                             {-0.5f, 0.8660254f}, {-0.8660254f, 0.5f}, {-1.0f, 0.0f}};

bool on(uint8_t channel) { return channel >= 128; }

} // namespace

Behaviour behaviourOfPixel(const uint8_t rgba[4]) {
  if (!on(rgba[3]))
    return Behaviour::None;
  const bool r = on(rgba[0]), g = on(rgba[1]), b = on(rgba[2]);
  if (r && g && !b)
    return Behaviour::Turn;
  if (r && !g && !b)
    return Behaviour::Wait;
  if (!r && g && !b)
    return Behaviour::Wander;
  if (!r && !g && b)
    return Behaviour::Attract;
  return Behaviour::None;
}

void AgentSettings::validate() const {
  auto check = [](bool ok, const char *field, const char *what) {
    if (!ok)
      throw Error(std::string("agent setting '") + field + "' " + what);
  };
  check(walkSpeed > 0 && walkSpeed < 20, "walk_speed", "must be in (0, 20) m/s");
  check(runSpeed > 0 && runSpeed < 20, "run_speed", "must be in (0, 20) m/s");
  check(runners >= 0 && runners <= 1, "runners", "must be in [0, 1]");
  check(radius > 0.01f && radius < 10, "radius", "must be in (0.01, 10) m");
  check(lookAhead >= 1 && lookAhead <= 16, "look_ahead", "must be 1 to 16 cells");
  check(turnRate > 0 && turnRate < 100, "turn_rate", "must be in (0, 100) radians a second");
  check(waitSeconds >= 0 && waitSeconds < 1e6f, "wait", "must be in [0, 1e6) seconds");
  check(step > 0 && step <= 1, "step", "must be in (0, 1] seconds");
}

std::function<void(Agent &, double)> holdUntilEvery(double period) {
  if (!(period > 0 && std::isfinite(period)))
    throw Error("a bus stop's period must be a positive number of seconds");
  return [period](Agent &a, double t) {
    a.holdUntil = std::max(a.holdUntil, (std::floor(t / period) + 1) * period);
  };
}

Crowd::Crowd(const pack::Terrain &terrain, const AgentSettings &settings)
    : terrain_(terrain), settings_(settings) {
  settings_.validate();
  occupancySide_ = 2 * settings_.radius;
  perSide_ = 1 / occupancySide_;
  perCell_ = 1 / terrain.cell;
  probesPerSide_ = uint32_t(std::max(1.0f, std::ceil(occupancySide_ / terrain.cell)));
  occupancyWidth_ = uint32_t(std::ceil(terrain.width * terrain.cell / occupancySide_));
  occupancyDepth_ = uint32_t(std::ceil(terrain.depth * terrain.cell / occupancySide_));
  occupancy_.assign(size_t(occupancyWidth_) * occupancyDepth_, 0);
  behaviours_.assign(terrain.cells(), uint8_t(Behaviour::None));
  callbackCells_.assign(terrain.cells(), 0);
}

namespace {

void checkImage(const char *what, uint32_t width, uint32_t height, const std::vector<uint8_t> &rgba,
                const pack::Terrain &t) {
  if (width != t.width || height != t.depth)
    throw Error(std::string(what) + " image is " + std::to_string(width) + "x" +
                std::to_string(height) + " pixels; the terrain's grid is " +
                std::to_string(t.width) + "x" + std::to_string(t.depth) + " cells");
  if (rgba.size() != size_t(width) * height * 4)
    throw Error(std::string(what) + " image: not width x height RGBA pixels");
}

} // namespace

void Crowd::setBehaviours(uint32_t width, uint32_t height, const std::vector<uint8_t> &rgba) {
  checkImage("the behaviour", width, height, rgba, terrain_);
  for (size_t i = 0; i < behaviours_.size(); ++i)
    behaviours_[i] = uint8_t(behaviourOfPixel(&rgba[4 * i]));
}

void Crowd::setCallbacks(uint32_t width, uint32_t height, const std::vector<uint8_t> &rgba,
                         std::vector<AgentCallback> callbacks) {
  checkImage("the callback", width, height, rgba, terrain_);
  if (callbacks.size() > 255)
    throw Error("more than 255 agent callbacks");
  callbacks_ = std::move(callbacks);
  for (size_t i = 0; i < callbackCells_.size(); ++i) {
    callbackCells_[i] = 0;
    for (size_t c = 0; c < callbacks_.size(); ++c)
      if (on(rgba[4 * i + 3]) && std::equal(callbacks_[c].rgb, callbacks_[c].rgb + 3, &rgba[4 * i]))
        callbackCells_[i] = uint8_t(c + 1);
  }
}

bool Crowd::standable(size_t cell) const {
  return cell != kNowhere && terrain_.ground[cell] == uint8_t(pack::Ground::Walkable);
}

bool Crowd::canStep(size_t cell, float fromHeight) const {
  return standable(cell) && std::abs(terrain_.heights[cell] - fromHeight) <= terrain_.stepHeight;
}

size_t Crowd::terrainCell(glm::vec2 p) const {
  const float x = (p.x - terrain_.originX) * perCell_;
  const float z = (p.y - terrain_.originZ) * perCell_;
  if (!(x >= 0 && z >= 0 && x < float(terrain_.width) && z < float(terrain_.depth)))
    return kNowhere;
  return terrain_.cellIndex(uint32_t(x), uint32_t(z));
}

size_t Crowd::occupancyCell(glm::vec2 p) const {
  const float x = (p.x - terrain_.originX) * perSide_;
  const float z = (p.y - terrain_.originZ) * perSide_;
  if (!(x >= 0 && z >= 0 && x < float(occupancyWidth_) && z < float(occupancyDepth_)))
    return kNowhere;
  return size_t(uint32_t(z)) * occupancyWidth_ + uint32_t(x);
}

double Crowd::random(size_t agent, uint64_t salt) const {
  const uint64_t h = mix(settings_.seed ^ mix(agent * 0x9E3779B97F4A7C15ull ^
                                              mix(figures_.steps * 0xC2B2AE3D27D4EB4Full ^ salt)));
  return double(h >> 11) * 0x1.0p-53;
}

Crowd::Ahead Crowd::clearAhead(size_t i, glm::vec2 dir) const {
  const Agent &a = agents_[i];
  // Every terrain cell on the way (probesPerSide_ a look-ahead cell): walkable, and no step up
  // or down past the limit; then the agent-sized cell at each look-ahead distance.
  const glm::vec2 step = dir * (occupancySide_ / float(probesPerSide_));
  glm::vec2 p = a.position;
  float height = a.height;
  for (uint32_t d = 1; d <= settings_.lookAhead; ++d) {
    for (uint32_t k = 0; k < probesPerSide_; ++k) {
      p += step;
      const size_t c = terrainCell(p);
      if (!canStep(c, height))
        return {d - 1, false};
      height = terrain_.heights[c];
    }
    const size_t o = occupancyCell(p);
    if (o != kNowhere && occupancy_[o] && occupancy_[o] != i + 1)
      return {d - 1, true};
  }
  return {settings_.lookAhead, false};
}

bool Crowd::enter(size_t i, glm::vec2 to) {
  Agent &a = agents_[i];
  const size_t c = terrainCell(to), o = occupancyCell(to);
  if (!canStep(c, a.height) || o == kNowhere)
    return false;
  if (occupancy_[o] != i + 1) {
    if (occupancy_[o])
      return false;
    occupancy_[occupancyCell(a.position)] = 0;
    occupancy_[o] = uint32_t(i + 1);
  }
  a.position = to;
  a.height = terrain_.heights[c];
  return true;
}

void Crowd::spawn(const std::vector<SpawnArea> &areas) {
  uint64_t total = agents_.size();
  for (const auto &area : areas)
    total += area.count;
  if (total > limits::kInstances)
    throw Error(std::to_string(total) + " agents asked for; at most " +
                std::to_string(limits::kInstances));
  // The free cells agents may stand on: more agents than these cannot be placed.
  std::vector<uint8_t> free(occupancy_.size(), 0);
  uint64_t capacity = 0;
  for (uint32_t z = 0; z < occupancyDepth_; ++z)
    for (uint32_t x = 0; x < occupancyWidth_; ++x) {
      const size_t o = size_t(z) * occupancyWidth_ + x;
      const glm::vec2 centre(terrain_.originX + (float(x) + 0.5f) * occupancySide_,
                             terrain_.originZ + (float(z) + 0.5f) * occupancySide_);
      free[o] = !occupancy_[o] && standable(terrainCell(centre));
      capacity += free[o];
    }
  if (total - agents_.size() > capacity)
    throw Error(std::to_string(total - agents_.size()) + " agents asked for, but the walkable " +
                "area holds at most " + std::to_string(capacity) + " more (one per " +
                std::to_string(occupancySide_) + " m cell)");
  auto centreOf = [&](size_t o) {
    return glm::vec2(terrain_.originX + (float(o % occupancyWidth_) + 0.5f) * occupancySide_,
                     terrain_.originZ + (float(o / occupancyWidth_) + 0.5f) * occupancySide_);
  };
  for (const auto &area : areas)
    for (uint32_t k = 0; k < area.count; ++k) {
      const size_t i = agents_.size();
      Agent a;
      glm::vec2 p =
          area.min + (area.max - area.min) * glm::vec2(float(random(i, 1)), float(random(i, 2)));
      const float eps = 1e-3f;
      p.x = std::clamp(p.x, terrain_.originX + eps,
                       terrain_.originX + float(occupancyWidth_) * occupancySide_ - eps);
      p.y = std::clamp(p.y, terrain_.originZ + eps,
                       terrain_.originZ + float(occupancyDepth_) * occupancySide_ - eps);
      size_t o = occupancyCell(p);
      if (o == kNowhere || !free[o] || !standable(terrainCell(p))) { // the nearest free cell's
        // centre, ring by ring (its own first: a cell's centre may stand where a corner of it
        // cannot, at a roof's edge)
        const long ox = long(o % occupancyWidth_), oz = long(o / occupancyWidth_);
        size_t best = kNowhere;
        float bestDistance = INFINITY;
        const long rings = long(std::max(occupancyWidth_, occupancyDepth_));
        for (long r = 0; r <= rings && best == kNowhere; ++r)
          for (long z = oz - r; z <= oz + r; ++z)
            for (long x = ox - r; x <= ox + r; ++x) {
              if ((std::abs(z - oz) != r && std::abs(x - ox) != r) || x < 0 || z < 0 ||
                  x >= long(occupancyWidth_) || z >= long(occupancyDepth_))
                continue;
              const size_t c = size_t(z) * occupancyWidth_ + size_t(x);
              const float distance = glm::length(centreOf(c) - p);
              if (free[c] && distance < bestDistance)
                best = c, bestDistance = distance;
            }
        figures_.spawnedMoved += best != o;
        o = best;
        p = centreOf(o);
      }
      free[o] = 0;
      occupancy_[o] = uint32_t(i + 1);
      a.position = p;
      a.height = terrain_.heights[terrainCell(p)];
      a.heading = float(random(i, 3) * 2 * kPi) - kPi;
      const bool runner = random(i, 4) < settings_.runners;
      a.cruise =
          (runner ? settings_.runSpeed : settings_.walkSpeed) * float(0.85 + 0.3 * random(i, 5));
      a.side = random(i, 6) < 0.5 ? 1 : -1;
      agents_.push_back(a);
      lastCell_.push_back(kNowhere);
    }
}

void Crowd::step() {
  const double t = time();
  const float dt = float(settings_.step), maxTurn = settings_.turnRate * dt;
  figures_.blockedNow = figures_.heldNow = 0;
  for (size_t i = 0; i < agents_.size(); ++i) {
    Agent &a = agents_[i];
    a.blocked = false;
    const size_t cell = terrainCell(a.position);
    if (cell != lastCell_[i]) {         // entering a zone (cells of one colour): its callback, then
      const size_t last = lastCell_[i]; // its behaviour, once until the agent leaves it
      lastCell_[i] = cell;
      if (callbackCells_[cell] &&
          (last == kNowhere || callbackCells_[last] != callbackCells_[cell]))
        callbacks_[callbackCells_[cell] - 1u].onEnter(a, t);
      const auto b = Behaviour(behaviours_[cell]);
      if (last == kNowhere || behaviours_[last] != behaviours_[cell]) {
        if (b == Behaviour::Wait)
          a.holdUntil = std::max(a.holdUntil, t + settings_.waitSeconds);
        else if (b == Behaviour::Turn)
          a.heading = wrapAngle(a.heading + float(a.side) * 0.5f * kPi);
      }
    }
    if (t < a.holdUntil) {
      a.speed = 0;
      ++figures_.heldNow;
      continue;
    }
    float want = a.heading;
    const auto b = Behaviour(behaviours_[cell]);
    if (b == Behaviour::Wander)
      want += float(random(i, 7) - 0.5) * 4 * maxTurn;
    else if (b == Behaviour::Attract && !attractors_.empty()) {
      glm::vec2 nearest = attractors_[0];
      for (const auto &p : attractors_)
        if (glm::length(p - a.position) < glm::length(nearest - a.position))
          nearest = p;
      const glm::vec2 d = nearest - a.position;
      if (glm::length(d) > 1e-3f)
        want = std::atan2(d.x, d.y);
    }
    // Look ahead; when something is in the way, the nearest free course, the preferred side
    // first: up to 180 degrees round a wall or a drop, a sidestep (30 or 60) round an agent.
    const glm::vec2 wantDir = direction(want);
    Ahead ahead = clearAhead(i, wantDir);
    const int turns = ahead.agent ? 2 : 6;
    float chosen = want;
    for (int k = 1; k <= turns && ahead.clear < settings_.lookAhead; ++k)
      for (int s : {int(a.side), -int(a.side)}) {
        const glm::vec2 r = kTurns[k - 1];
        const float sin = float(s) * r.y; // want's direction turned by s * k * 30 degrees
        const Ahead c =
            clearAhead(i, {wantDir.x * r.x + wantDir.y * sin, wantDir.y * r.x - wantDir.x * sin});
        if (c.clear > ahead.clear) {
          ahead = c, chosen = want + float(s * k) * kPi / 6;
          if (c.clear == settings_.lookAhead)
            break;
        }
      }
    want = chosen;
    a.heading = wrapAngle(a.heading + std::clamp(wrapAngle(want - a.heading), -maxTurn, maxTurn));
    if (clearAhead(i, direction(a.heading)).clear >= 1 &&
        enter(i, a.position + direction(a.heading) * (a.cruise * dt))) {
      a.speed = a.cruise;
    } else {
      a.speed = 0;
      a.blocked = true;
      ++figures_.blockedNow;
    }
  }
  figures_.blockedAgentSteps += figures_.blockedNow;
  ++figures_.steps;
}

} // namespace crowd::runtime
