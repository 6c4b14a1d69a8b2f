#include "crowd/runtime/world.h"

#include <cmath>
#include <functional>

#include "crowd/formats/error.h"

namespace crowd::runtime {

namespace {
constexpr float kStillSeconds = 0.25f; // still this long, an agent stands (the idle clip)
}

SceneWorld::SceneWorld(const Scene &scene, pack::Terrain terrain, const RgbaImage &behaviours,
                       const RgbaImage &callbacks)
    : scene_(scene), terrain_(std::move(terrain)), behaviours_(behaviours), callbacks_(callbacks) {
  restart();
}

void SceneWorld::restart() {
  const WorldSettings &w = scene_.world;
  crowd_ = std::make_unique<Crowd>(terrain_, w.agents);
  auto named = [](const std::string &path, const std::function<void()> &set) {
    try {
      set();
    } catch (const Error &e) {
      throw Error(path + ": " + e.what());
    }
  };
  if (!behaviours_.rgba.empty())
    named(w.behaviourPath,
          [&] { crowd_->setBehaviours(behaviours_.width, behaviours_.height, behaviours_.rgba); });
  if (!callbacks_.rgba.empty()) {
    std::vector<AgentCallback> stops;
    for (const auto &b : w.busStops)
      stops.push_back(
          {"bus_stop", {b.colour[0], b.colour[1], b.colour[2]}, holdUntilEvery(b.every)});
    named(w.callbackPath, [&] {
      crowd_->setCallbacks(callbacks_.width, callbacks_.height, callbacks_.rgba, stops);
    });
  }
  for (const auto &a : w.attractors)
    crowd_->addAttractor(a);
  named(scene_.path, [&] { crowd_->spawn(w.spawn); });
  if (crowd_->agents().size() != scene_.instances.size())
    throw Error(scene_.path + ": the world spawns " + std::to_string(crowd_->agents().size()) +
                " agents for " + std::to_string(scene_.instances.size()) + " instances");
  motions_.assign(scene_.instances.size(), {});
  still_.assign(scene_.instances.size(), 0.0f);
  started_ = false;
  last_ = 0;
  advanceTo(0);
}

void SceneWorld::advanceTo(double seconds) {
  const WorldSettings &w = scene_.world;
  if (seconds < crowd_->time() - 1e-9)
    restart(); // a simulation only runs forward
  while (crowd_->time() + w.agents.step <= seconds + 1e-9)
    crowd_->step();
  const double now = crowd_->time();
  for (size_t i = 0; i < motions_.size(); ++i) {
    const Agent &a = crowd_->agents()[i];
    InstanceMotion &m = motions_[i];
    m.position = {a.position.x, a.height, a.position.y};
    m.yaw = a.heading;
    // The pace: standing, walking or running; walk and run at the agent's own cruising speed,
    // so that the feet keep pace with the ground. Before the first step every agent is on its
    // way, at its instance's time offset.
    const bool running = a.cruise > 0.5f * (w.agents.walkSpeed + w.agents.runSpeed);
    // Standing only once still for a moment: a step held up by another agent keeps the pace.
    still_[i] = a.speed <= 0 ? still_[i] + float(now - last_) : 0.0f;
    const uint32_t pace = started_ && still_[i] >= kStillSeconds ? 0 : running ? 2 : 1;
    const float speed =
        pace == 0 ? 1.0f : a.cruise / (running ? w.agents.runSpeed : w.agents.walkSpeed);
    ClipState &c = m.clip;
    if (!started_) {
      c = {};
      c.clip = w.clips[pace];
      c.offset = scene_.instances[i].timeOffset;
    } else if (w.clips[pace] != c.clip) { // a new pace: fade from the old clip, played on
      c.from = int32_t(c.clip);
      c.fromOffset = (now * m.speed + c.offset) - now * speed;
      c.fadeStart = now;
      c.fadeSeconds = w.fade;
      c.clip = w.clips[pace];
      c.offset = -now * speed; // from its first frame
    } else if (c.from >= 0 && c.weightAt(now) >= 1.0f) {
      c.from = -1; // the fade is over
    }
    m.speed = speed;
  }
  started_ = true;
  last_ = now;
}

} // namespace crowd::runtime
