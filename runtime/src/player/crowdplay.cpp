// crowdplay: loads crowdpacks and draws a scene's crowd with skinned instancing. Interactive in a
// window, or headless (offscreen, fixed time step) for screenshots, stats and benchmarks.
// GLFW must not pull in GL headers of its own: libepoxy provides them.
#define GLFW_INCLUDE_NONE
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include <GLFW/glfw3.h>
#include <OpenImageIO/imageio.h>
#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "crowd/formats/chunks.h"
#include "crowd/formats/error.h"
#include "crowd/formats/impostor.h"
#include "crowd/formats/limits.h"
#include "crowd/runtime/character_types.h"
#include "crowd/runtime/preview_scene.h"
#include "crowd/runtime/crowd_renderer.h"
#include "crowd/runtime/scene.h"

namespace {

const char *kHelp = R"(usage: crowdplay SCENE.json [options]

Draws the scene's crowd from baked packs with skinned instancing (one instanced multi-draw per
sub-mesh per character type). Instances outside the view are culled by a sphere that holds the
character at every frame. Under a triangle budget (--budget, or "budget" in the scene), each
visible instance of a pack with LOD (crowdbake lod) gets a level of detail: the budget is
shared by weights from projected area and distance. Where a scene pack names an impostor pack,
instances playing the impostor's clip draw as impostors once one impostor texel is no bigger
than a pixel (all of a type in one more instanced draw). In a clothed pack (crowdbake outfits)
each instance wears the outfit the scene gives it ("outfit": a name, a list, or {name: weight})
and draws only the body parts it leaves visible: each frame, a render queue per sub-mesh holds
the visible instances that draw it, one instanced draw each. Without --headless a window
opens: drag with the left mouse button to orbit, scroll to zoom, W/A/S/D to move, Esc to quit;
the title shows frame time, visible instances, triangles against the budget and draw calls.

options:
  --headless           render offscreen (run under xvfb-run -a where there is no display)
  --frames N           frames to render headless (default 60), at a fixed 1/30 s step
  --size WxH           image size (default 1280x720)
  --instances K        override the scene's instance count (its placement rule stays)
  --screenshot FILE    write the last frame as PNG
  --stats FILE         write per-frame frame_ms, gpu_ms, cull_select_ms, draw_calls,
                       instances, visible, impostors, triangles (an impostor counts two) and
                       their means under "summary" (with the budget); vertices: vertex
                       shader invocations, where the driver counts them
  --budget N           triangles a frame (0: none, full detail; default: the scene's)
  --no-cull            draw instances outside the view too (the reference for culling)
  --naive              one draw per instance per sub-mesh, instance data in uniforms (no
                       culling, LOD or impostors)
  --geometry           instanced geometry only: no impostors (the baseline of the hybrid)
  --whole-body         clothed packs: draw the whole body under the garments (the naive
                       method, for comparison) instead of each outfit's visible sub-meshes
  --time SECONDS       scene time of the first frame (default 0)
  --step SECONDS       headless time step between frames (default 1/30)

example:
  xvfb-run -a crowdplay samples/scenes/demo.json --headless --frames 120 --screenshot a.png --stats s.json
)";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Options {
  std::string scene, screenshot, stats;
  bool headless = false;
  crowd::runtime::DrawOptions draw;
  long budget = -1; // -1: the scene's
  int frames = 60, width = 1280, height = 720;
  size_t instances = 0;
  double startTime = 0, step = 1.0 / 30.0;
};

Options parse(int argc, char **argv) {
  Options o;
  auto value = [&](int &i) {
    if (i + 1 >= argc)
      throw UsageError(std::string(argv[i]) + " needs a value");
    return std::string(argv[++i]);
  };
  auto integer = [&](const std::string &s, const char *what, long lo, long hi) {
    try {
      size_t used = 0;
      long v = std::stol(s, &used);
      if (used == s.size() && v >= lo && v <= hi)
        return v;
    } catch (const std::exception &) {
    }
    throw UsageError(std::string(what) + " expects an integer in [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "], got '" + s + "'");
  };
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--headless")
      o.headless = true;
    else if (a == "--naive")
      o.draw.path = crowd::runtime::DrawPath::Naive;
    else if (a == "--geometry")
      o.draw.path = crowd::runtime::DrawPath::Instanced;
    else if (a == "--no-cull")
      o.draw.cull = false;
    else if (a == "--whole-body")
      o.draw.wholeBody = true;
    else if (a == "--budget")
      o.budget = integer(value(i), "--budget", 0, 1000000000000L);
    else if (a == "--frames")
      o.frames = int(integer(value(i), "--frames", 1, 1000000));
    else if (a == "--instances")
      o.instances = size_t(integer(value(i), "--instances", 1, long(crowd::limits::kInstances)));
    else if (a == "--screenshot")
      o.screenshot = value(i);
    else if (a == "--stats")
      o.stats = value(i);
    else if (a == "--time" || a == "--step") {
      std::string v = value(i);
      double seconds;
      try {
        seconds = std::stod(v);
      } catch (const std::exception &) {
        throw UsageError(a + " expects seconds, got '" + v + "'");
      }
      if (!std::isfinite(seconds) || (a == "--step" && seconds < 0))
        throw UsageError(a + " expects finite, non-negative seconds, got '" + v + "'");
      (a == "--time" ? o.startTime : o.step) = seconds;
    } else if (a == "--size") {
      std::string v = value(i);
      auto x = v.find('x');
      if (x == std::string::npos)
        throw UsageError("--size expects WxH, got '" + v + "'");
      o.width = int(integer(v.substr(0, x), "--size width", 16, crowd::limits::kScreenSide));
      o.height = int(integer(v.substr(x + 1), "--size height", 16, crowd::limits::kScreenSide));
    } else if (a.rfind("--", 0) == 0) {
      throw UsageError("unknown option " + a);
    } else if (o.scene.empty()) {
      o.scene = a;
    } else {
      throw UsageError("one scene file only");
    }
  }
  if (o.scene.empty())
    throw UsageError("no scene file (see crowdplay --help)");
  return o;
}

crowd::runtime::FrameView frameView(const crowd::runtime::Camera &cam, double t, int width,
                                    int height) {
  glm::dvec3 eye, target;
  cam.at(t, eye, target);
  crowd::runtime::FrameView v;
  v.fovY = glm::radians(cam.fovYDegrees);
  v.viewportHeight = height;
  v.eye = glm::vec3(eye);
  v.viewProjection = glm::mat4(
      glm::perspective(v.fovY, double(width) / std::max(height, 1), cam.nearPlane, cam.farPlane) *
      glm::lookAt(eye, target, glm::dvec3(0, 1, 0)));
  return v;
}

const char *pathName(crowd::runtime::DrawPath p) {
  return p == crowd::runtime::DrawPath::Naive       ? "naive"
         : p == crowd::runtime::DrawPath::Instanced ? "instanced"
                                                    : "hybrid";
}

std::string budgetText(uint64_t budget) {
  if (!budget)
    return "no budget";
  char text[64];
  std::snprintf(text, sizeof text, "budget %.2f M", double(budget) / 1e6);
  return text;
}

void writePng(const std::string &path, int w, int h, const std::vector<uint8_t> &rgba) {
  std::vector<uint8_t> rgb(size_t(w) * size_t(h) * 3);
  for (int y = 0; y < h; ++y) // GL rows start at the bottom
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < 3; ++k)
        rgb[(size_t(y) * size_t(w) + size_t(x)) * 3 + size_t(k)] =
            rgba[(size_t(h - 1 - y) * size_t(w) + size_t(x)) * 4 + size_t(k)];
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::UINT8);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, rgb.data()) ||
      !out->close())
    throw crowd::Error(path + ": cannot write screenshot");
}

struct Glfw {
  Glfw() {
    glfwSetErrorCallback([](int, const char *) {});
    if (!glfwInit())
      throw crowd::Error("cannot initialise GLFW (no display? run under xvfb-run -a)");
  }
  ~Glfw() { glfwTerminate(); }
};

GLFWwindow *openWindow(int w, int h, bool visible) {
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_VISIBLE, visible ? GLFW_TRUE : GLFW_FALSE);
  GLFWwindow *win = glfwCreateWindow(w, h, "crowdplay", nullptr, nullptr);
  if (!win) {
    const char *why = nullptr;
    glfwGetError(&why);
    throw crowd::Error(std::string("cannot create an OpenGL 4.5 core context: ") +
                       (why ? why : "unknown reason"));
  }
  glfwMakeContextCurrent(win);
  if (epoxy_gl_version() < 45)
    throw crowd::Error("OpenGL 4.5 is required, the driver offers " +
                       std::to_string(epoxy_gl_version() / 10) + "." +
                       std::to_string(epoxy_gl_version() % 10));
  return win;
}

int headless(const Options &o, crowd::runtime::CrowdRenderer &renderer,
             const crowd::runtime::Scene &scene) {
  unsigned fbo, colour, depth, query;
  glCreateFramebuffers(1, &fbo);
  glCreateRenderbuffers(1, &colour);
  glCreateRenderbuffers(1, &depth);
  glNamedRenderbufferStorage(colour, GL_RGBA8, o.width, o.height);
  glNamedRenderbufferStorage(depth, GL_DEPTH_COMPONENT24, o.width, o.height);
  glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
  glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
  if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw crowd::Error("cannot create a " + std::to_string(o.width) + "x" +
                       std::to_string(o.height) + " offscreen target");
  glCreateQueries(GL_TIME_ELAPSED, 1, &query);
  // Vertex shader invocations, as the driver counts them (ARB_pipeline_statistics_query).
  unsigned vertexQuery = 0;
  if (epoxy_has_gl_extension("GL_ARB_pipeline_statistics_query"))
    glGenQueries(1, &vertexQuery); // Mesa 22 refuses this target in glCreateQueries
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glViewport(0, 0, o.width, o.height);
  glEnable(GL_DEPTH_TEST);
  nlohmann::ordered_json frames = nlohmann::ordered_json::array();
  const char *keys[9] = {"frame_ms", "gpu_ms",    "cull_select_ms", "draw_calls", "instances",
                         "visible",  "impostors", "triangles",      "vertices"};
  const int columns = vertexQuery ? 9 : 8;
  double sums[9] = {};
  for (int f = 0; f < o.frames; ++f) {
    double t = o.startTime + f * o.step;
    auto t0 = std::chrono::steady_clock::now();
    glClearColor(0.55f, 0.62f, 0.70f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glBeginQuery(GL_TIME_ELAPSED, query);
    if (vertexQuery)
      glBeginQuery(GL_VERTEX_SHADER_INVOCATIONS_ARB, vertexQuery);
    auto stats = renderer.draw(frameView(scene.camera, t, o.width, o.height), float(t), o.draw);
    if (vertexQuery)
      glEndQuery(GL_VERTEX_SHADER_INVOCATIONS_ARB);
    glEndQuery(GL_TIME_ELAPSED);
    glFinish();
    double frameMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    GLuint64 ns = 0, vertices = 0;
    glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
    if (vertexQuery)
      glGetQueryObjectui64v(vertexQuery, GL_QUERY_RESULT, &vertices);
    double v[9] = {frameMs,
                   double(ns) / 1e6,
                   stats.cullSelectMs,
                   double(stats.drawCalls),
                   double(stats.instances),
                   double(stats.visible),
                   double(stats.impostors),
                   double(stats.triangles),
                   double(vertices)};
    nlohmann::ordered_json row = {{"frame", f}, {"time_s", t}};
    for (int k = 0; k < columns; ++k) {
      row[keys[k]] = k < 3 ? nlohmann::ordered_json(v[k]) : nlohmann::ordered_json(uint64_t(v[k]));
      sums[k] += v[k];
    }
    frames.push_back(row);
  }
  if (!o.screenshot.empty()) {
    std::vector<uint8_t> rgba(size_t(o.width) * size_t(o.height) * 4);
    glReadPixels(0, 0, o.width, o.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    writePng(o.screenshot, o.width, o.height, rgba);
  }
  nlohmann::ordered_json summary;
  summary["frames"] = o.frames;
  for (int k = 0; k < columns; ++k)
    summary[keys[k]] = sums[k] / o.frames;
  summary["whole_body"] = o.draw.wholeBody;
  summary["budget"] = o.draw.budget;
  summary["renderer"] = reinterpret_cast<const char *>(glGetString(GL_RENDERER));
  summary["path"] = pathName(o.draw.path);
  summary["size"] = std::to_string(o.width) + "x" + std::to_string(o.height);
  if (!o.stats.empty()) {
    std::ofstream f(o.stats);
    f << nlohmann::ordered_json{{"summary", summary}, {"frames", frames}}.dump(2) << "\n";
    if (!f)
      throw crowd::Error(o.stats + ": cannot write stats");
  }
  std::printf("%d frames, %s: %.2f ms/frame (gpu %.2f ms, cull + select %.3f ms), %.0f draw "
              "calls, %.0f instances, %.0f visible (%.0f impostors), %.0f triangles (%s)\n",
              o.frames, pathName(o.draw.path), sums[0] / o.frames, sums[1] / o.frames,
              sums[2] / o.frames, sums[3] / o.frames, sums[4] / o.frames, sums[5] / o.frames,
              sums[6] / o.frames, sums[7] / o.frames, budgetText(o.draw.budget).c_str());
  return 0;
}

struct Orbit {
  double yaw = 0, pitch = 0, distance = 1, lastX = 0, lastY = 0;
  glm::dvec3 pan{0};
  bool dragging = false;
};

int interactive(GLFWwindow *win, const Options &o, crowd::runtime::CrowdRenderer &renderer,
                crowd::runtime::Scene scene) {
  Orbit orbit;
  glm::dvec3 d = scene.camera.position - scene.camera.target;
  orbit.distance = glm::length(d);
  orbit.yaw = std::atan2(d.x, d.z);
  orbit.pitch = std::asin(d.y / std::max(orbit.distance, 1e-9));
  glfwSetWindowUserPointer(win, &orbit);
  glfwSetScrollCallback(win, [](GLFWwindow *w, double, double dy) {
    auto *ob = static_cast<Orbit *>(glfwGetWindowUserPointer(w));
    ob->distance *= std::pow(0.9, dy);
  });
  glEnable(GL_DEPTH_TEST);
  auto start = std::chrono::steady_clock::now(), lastTitle = start;
  double frameMs = 0;
  bool userCamera = false;
  while (!glfwWindowShouldClose(win)) {
    auto t0 = std::chrono::steady_clock::now();
    double t = o.startTime + std::chrono::duration<double>(t0 - start).count();
    double mx, my;
    glfwGetCursorPos(win, &mx, &my);
    bool down = glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    if (down && orbit.dragging) {
      orbit.yaw -= (mx - orbit.lastX) * 0.005;
      orbit.pitch = std::clamp(orbit.pitch + (my - orbit.lastY) * 0.005, -1.5, 1.5);
      userCamera = true;
    }
    orbit.dragging = down;
    orbit.lastX = mx, orbit.lastY = my;
    glm::dvec3 forward(-std::sin(orbit.yaw), 0, -std::cos(orbit.yaw)),
        right(-forward.z, 0, forward.x);
    double step = orbit.distance * 0.02;
    if (glfwGetKey(win, GLFW_KEY_W) == GLFW_PRESS)
      orbit.pan += forward * step, userCamera = true;
    if (glfwGetKey(win, GLFW_KEY_S) == GLFW_PRESS)
      orbit.pan -= forward * step, userCamera = true;
    if (glfwGetKey(win, GLFW_KEY_D) == GLFW_PRESS)
      orbit.pan += right * step, userCamera = true;
    if (glfwGetKey(win, GLFW_KEY_A) == GLFW_PRESS)
      orbit.pan -= right * step, userCamera = true;
    if (glfwGetKey(win, GLFW_KEY_ESCAPE) == GLFW_PRESS)
      glfwSetWindowShouldClose(win, 1);
    if (userCamera) { // the user took over from the scene's camera path
      scene.camera.path.clear();
      scene.camera.target = scene.camera.target + orbit.pan;
      orbit.pan = glm::dvec3(0);
      scene.camera.position =
          scene.camera.target +
          orbit.distance * glm::dvec3(std::cos(orbit.pitch) * std::sin(orbit.yaw),
                                      std::sin(orbit.pitch),
                                      std::cos(orbit.pitch) * std::cos(orbit.yaw));
    }
    int w, h;
    glfwGetFramebufferSize(win, &w, &h);
    glViewport(0, 0, w, h);
    glClearColor(0.55f, 0.62f, 0.70f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    auto stats = renderer.draw(frameView(scene.camera, t, w, h), float(t), o.draw);
    glfwSwapBuffers(win);
    glfwPollEvents();
    auto t1 = std::chrono::steady_clock::now();
    frameMs = 0.9 * frameMs + 0.1 * std::chrono::duration<double, std::milli>(t1 - t0).count();
    if (t1 - lastTitle > std::chrono::milliseconds(500)) {
      char title[256];
      std::snprintf(title, sizeof title,
                    "crowdplay  %.1f ms  %u of %u visible (%u impostors)  %.2f M triangles (%s)  "
                    "%u draw calls  cull + select %.2f ms",
                    frameMs, stats.visible, stats.instances, stats.impostors,
                    double(stats.triangles) / 1e6, budgetText(o.draw.budget).c_str(),
                    stats.drawCalls, stats.cullSelectMs);
      glfwSetWindowTitle(win, title);
      lastTitle = t1;
    }
  }
  return 0;
}

} // namespace

int main(int argc, char **argv) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      std::cout << kHelp;
      return 0;
    }
  try {
    Options o = parse(argc, argv);
    // A pack without a scene file: the preview scene of its clips and outfits.
    const bool previewPack = std::filesystem::path(o.scene).extension() == ".crowdpack";
    crowd::runtime::Scene scene =
        previewPack ? crowd::runtime::previewScene(
                          o.scene, crowd::pack::loadCharacterPack(crowd::pack::Reader::open(o.scene)))
                    : crowd::runtime::loadScene(o.scene, o.instances);
    o.draw.budget = o.budget >= 0 ? uint64_t(o.budget) : scene.budget;
    std::vector<crowd::pack::CharacterPack> packs;
    for (const auto &path : scene.packPaths) {
      if (!std::filesystem::exists(path))
        throw crowd::Error(o.scene + ": pack '" + path +
                           "' does not exist (bake it first: ./run demo)");
      packs.push_back(crowd::pack::loadCharacterPack(crowd::pack::Reader::open(path)));
    }
    std::vector<crowd::pack::ImpostorPack> impostorPacks(scene.impostorPaths.size());
    std::vector<const crowd::pack::Impostor *> impostors(scene.impostorPaths.size(), nullptr);
    for (size_t k = 0; k < scene.impostorPaths.size(); ++k) {
      const std::string &path = scene.impostorPaths[k];
      if (path.empty())
        continue;
      if (!std::filesystem::exists(path))
        throw crowd::Error(o.scene + ": impostor pack '" + path +
                           "' does not exist (bake it: crowdbake impostor)");
      impostorPacks[k] = crowd::pack::loadImpostorPack(crowd::pack::Reader::open(path));
      impostors[k] = &impostorPacks[k].impostor;
    }
    Glfw glfw;
    GLFWwindow *win =
        openWindow(o.headless ? 64 : o.width, o.headless ? 64 : o.height, !o.headless);
    auto types = crowd::runtime::characterTypes(scene, packs, impostors);
    crowd::runtime::CrowdRenderer renderer(types.packs, types.impostors, scene);
    int rc = o.headless ? headless(o, renderer, scene) : interactive(win, o, renderer, scene);
    return rc;
  } catch (const UsageError &e) {
    std::fprintf(stderr, "crowdplay: usage: %s\n", e.what());
    return 2;
  } catch (const std::exception &e) {
    std::string msg = e.what();
    for (char &ch : msg)
      if (ch == '\n')
        ch = ' ';
    std::fprintf(stderr, "crowdplay: error: %s\n", msg.c_str());
    return 1;
  }
}
