// Agents on a baked terrain (Tecchia, Loscos & Chrysanthou, §2 and §3): a crowd moved
// at a fixed time step over four layers of the terrain's grid, with no GL. Deterministic: agents
// move one after another in index order, and every random choice is a hash of (seed, agent,
// step), so the same settings give the same crowd at the same step on any machine.
//  1. Environment: an agent stands on the height map; it moves onto a cell only if that cell is
//     walkable and the step to it is at most the terrain's step height; it looks `lookAhead`
//     occupancy cells ahead, so it turns before it reaches a wall or a drop, not at it.
//  2. Inter-collision: an occupancy grid of agent-sized cells, each held by at most one agent;
//     an agent does not enter a held cell, and treats held cells ahead as obstacles too.
//  3. Behaviour: per cell, a Behaviour named by a colour of an RGBA image the size of the grid;
//     Wait and Turn act once as an agent enters a zone of their colour, the others every step.
//  4. Callbacks: per cell, a named callback (a colour of a second image) run when an agent
//     enters a zone of its colour, e.g. a bus stop that holds agents and releases them on a
//     timer.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "crowd/formats/terrain.h"

namespace crowd::runtime {

enum class Behaviour : uint8_t {
  None = 0, // keep the course (white, black or transparent pixels)
  Wander,   // green: small random turns
  Wait,     // red: stop for AgentSettings::waitSeconds on entering
  Attract,  // blue: steer towards the nearest attractor
  Turn,     // yellow: turn a quarter to the agent's preferred side on entering
};
// The behaviour a pixel names: each channel read as on (>= 128) or off; alpha < 128 is None.
Behaviour behaviourOfPixel(const uint8_t rgba[4]);

struct AgentSettings {
  float walkSpeed = 1.3f; // m/s, the mean of the walkers' cruising speeds (+-15%)
  float runSpeed = 3.2f;  // m/s, the runners'
  float runners = 0.1f;   // the share of agents that run
  float radius = 0.25f;   // the occupancy grid's cells are 2 * radius on a side
  uint32_t lookAhead = 3; // occupancy cells an agent looks ahead
  float turnRate = 3.0f;  // radians a second at most
  float waitSeconds = 4;  // a Wait cell holds an agent this long
  double step = 1.0 / 30; // seconds a step
  uint64_t seed = 1;
  void validate() const; // throws crowd::Error naming the field
};

struct Agent {
  glm::vec2 position{0}; // world x, z
  float height = 0;      // world y: the surface under it
  float heading = 0;     // radians about +y; 0 walks towards +z, pi/2 towards +x
  float speed = 0;       // this step's speed (m/s): 0 while held or blocked
  float cruise = 0;      // its own speed when free
  double holdUntil = 0;  // held (a Wait cell, a callback) until this time
  bool blocked = false;  // it wanted to move but could not this step
  int8_t side = 1;       // the side it prefers to turn to (+1 left, -1 right)
};

// A named callback a cell colour triggers when an agent enters the cell.
struct AgentCallback {
  std::string name;
  uint8_t rgb[3] = {0, 0, 0};
  std::function<void(Agent &, double time)> onEnter;
};
// The bus stop: holds an agent until the next multiple of `period` seconds.
std::function<void(Agent &, double)> holdUntilEvery(double period);

struct SpawnArea {
  glm::vec2 min{0}, max{0}; // world x, z
  uint32_t count = 0;
};

struct CrowdFigures {
  uint64_t steps = 0;
  uint64_t blockedAgentSteps = 0; // over every step so far
  uint32_t blockedNow = 0;        // agents blocked in the last step
  uint32_t heldNow = 0;           // agents held (waiting) in the last step
  uint32_t spawnedMoved = 0;      // spawned on a blocked cell, moved to the nearest walkable
};

class Crowd {
public:
  Crowd(const pack::Terrain &terrain, const AgentSettings &settings);

  // The behaviour image: `width` x `height` RGBA8, row 0 at the lowest z, the terrain's size.
  void setBehaviours(uint32_t width, uint32_t height, const std::vector<uint8_t> &rgba);
  // The callback image (same layout): a pixel whose RGB is a callback's calls it on entry.
  void setCallbacks(uint32_t width, uint32_t height, const std::vector<uint8_t> &rgba,
                    std::vector<AgentCallback> callbacks);
  void addAttractor(glm::vec2 position) { attractors_.push_back(position); }

  // Places agents at seeded random points of each area (clamped to the grid). One that lands on
  // a cell it cannot stand on, or that another holds, goes to the nearest free walkable cell.
  // At most limits::kInstances agents in all.
  void spawn(const std::vector<SpawnArea> &areas);

  void step(); // one fixed step

  double time() const { return double(figures_.steps) * settings_.step; }
  const std::vector<Agent> &agents() const { return agents_; }
  const CrowdFigures &figures() const { return figures_; }

private:
  bool standable(size_t cell) const;
  // Whether an agent at `fromHeight` may step onto the cell: walkable, and no step up or down
  // past the terrain's step height. The one rule for the look-ahead and the move.
  bool canStep(size_t cell, float fromHeight) const;
  size_t terrainCell(glm::vec2 p) const;   // SIZE_MAX outside the grid
  size_t occupancyCell(glm::vec2 p) const; // SIZE_MAX outside the grid
  struct Ahead {
    uint32_t clear = 0; // look-ahead probes clear of walls, drops and agents
    bool agent = false; // the first obstacle is another agent
  };
  Ahead clearAhead(size_t agent, glm::vec2 direction) const;
  bool enter(size_t agent, glm::vec2 to);           // moves it if the destination is free
  double random(size_t agent, uint64_t salt) const; // in [0, 1)

  const pack::Terrain &terrain_;
  AgentSettings settings_;
  std::vector<Agent> agents_;
  std::vector<uint8_t> behaviours_;    // per terrain cell: Behaviour
  std::vector<uint8_t> callbackCells_; // per terrain cell: callback index + 1
  std::vector<AgentCallback> callbacks_;
  std::vector<glm::vec2> attractors_;
  float occupancySide_ = 0.5f, perSide_ = 2, perCell_ = 4;
  uint32_t probesPerSide_ = 2; // terrain cells probed per look-ahead cell
  uint32_t occupancyWidth_ = 0, occupancyDepth_ = 0;
  std::vector<uint32_t> occupancy_; // agent index + 1, 0: free
  std::vector<size_t> lastCell_;    // per agent: the terrain cell it stood on last step
  CrowdFigures figures_;
};

} // namespace crowd::runtime
