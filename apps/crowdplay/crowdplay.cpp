// crowdplay: loads crowdpacks and draws a scene's crowd with skinned instancing. Interactive in a
// window, or headless (offscreen, fixed time step) for screenshots, stats and benchmarks.
// GLFW must not pull in GL headers of its own: libepoxy provides them.
#define GLFW_INCLUDE_NONE
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <GLFW/glfw3.h>
#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "crowd/formats/chunks.h"
#include "crowd/formats/error.h"
#include "crowd/formats/file_read.h"
#include "crowd/formats/impostor.h"
#include "crowd/formats/limits.h"
#include "crowd/formats/registry.h"
#include "crowd/formats/terrain.h"
#include "crowd/formats/version.h"
#include "crowd/runtime/character_types.h"
#include "crowd/runtime/crowd_renderer.h"
#include "crowd/runtime/headless_gl.h"
#include "crowd/runtime/preview_scene.h"
#include "crowd/runtime/scene.h"
#include "crowd/support/images.h"

namespace {

const char *kAbout = R"(crowdplay: draws a scene's crowd from baked packs, or previews one pack

usage: crowdplay SCENE.json [options]
       crowdplay PACK.crowdpack [options]

Skinned instancing: one instanced multi-draw per sub-mesh per character type. Instances outside
the view are culled by a sphere that holds the character at every frame. Under a triangle budget
(--budget, or "budget" in the scene), each visible instance of a pack with LOD gets a level of
detail: the budget is shared by weights from projected area and distance. Instances playing a
clip that has an impostor (a character pack's, or the impostor pack a scene names) draw as
impostors once one impostor texel is no bigger than a pixel (all of a type in one more instanced
draw). In a clothed pack each instance wears the outfit the scene gives it ("outfit": a name, a
list, or {name: weight}) and draws only the body parts it leaves visible, through a render queue
per sub-mesh. With "switch" in a scene's instances ({"every": {"min": 3, "max": 8}, "fade": 0.3})
each instance changes clip every 3 to 8 s, crossfading over 0.3 s on the GPU.

A pack given without a scene file is previewed: every (clip, outfit) pair in a row framed by the
pack's bounding sphere, the same row far behind (where impostors take over), and a turntable
camera. --clip and --outfit narrow the row.

Without --headless a window opens: drag with the left mouse button to orbit, scroll to zoom,
W/A/S/D to move, Esc to quit. Keys: C next clip (crossfading from one clip to the next), O next outfit (pack previews), L next level of
detail (auto, 100%, 50%, 25%, 10%, 5%), I next drawing (hybrid, geometry only, impostors only).
The title shows the choice, frame time, visible instances, triangles against the budget and draw
calls.)";

struct Options {
  std::string scene, screenshot, stats, clip, outfit;
  bool headless = false;
  crowd::runtime::DrawOptions draw;
  long budget = -1;        // -1: the scene's
  std::string paletteSlot; // "": the scene's
  int frames = 60, width = 1280, height = 720;
  size_t instances = 0;
  double startTime = 0, step = 1.0 / 30.0;
  bool previewPack() const { return std::filesystem::path(scene).extension() == ".crowdpack"; }
};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// False when --help was asked for (printed on stdout).
bool parse(int argc, char **argv, Options &o) {
  CLI::App app(kAbout, "crowdplay");
  app.add_option("SCENE", o.scene, "a scene (.json) or a pack to preview (.crowdpack)")->required();
  app.add_flag("--headless", o.headless,
               "render offscreen at a fixed time step: through EGL without a display (a GPU's "
               "driver or Mesa), else in a hidden window (then run under xvfb-run -a)");
  app.add_option("--frames", o.frames, "frames to render headless")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  std::string size = "1280x720";
  app.add_option("--size", size, "image size, WxH")->capture_default_str();
  app.add_option("--instances", o.instances,
                 "override the scene's instance count (its placement rule stays)")
      ->check(CLI::Range(size_t(1), size_t(crowd::limits::kInstances)));
  app.add_option("--screenshot", o.screenshot, "write the last headless frame as PNG");
  app.add_option("--stats", o.stats,
                 "write per-frame frame_ms, gpu_ms, cull_select_ms, draw_calls, instances, "
                 "visible, impostors, triangles (an impostor counts two) and vertices (vertex "
                 "shader invocations, where the driver counts them), and their means under "
                 "\"summary\", as JSON");
  app.add_option("--budget", o.budget,
                 "triangles a frame (0: none, full detail; default: the scene's)")
      ->check(CLI::Range(0L, 1000000000000L));
  app.add_option("--detail", o.draw.detail,
                 "every geometry instance at this share of its full detail's triangles, "
                 "whatever the budget (0: chosen under the budget)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_flag_callback(
      "--no-cull", [&] { o.draw.cull = false; },
      "draw instances outside the view too (the reference for culling)");
  auto *naive = app.add_flag_callback(
      "--naive", [&] { o.draw.path = crowd::runtime::DrawPath::Naive; },
      "one draw per instance per sub-mesh, instance data in uniforms (no culling, LOD or "
      "impostors)");
  auto *geometry = app.add_flag_callback(
      "--geometry", [&] { o.draw.path = crowd::runtime::DrawPath::Instanced; },
      "instanced geometry only: no impostors (the baseline of the hybrid)");
  auto *impostors = app.add_flag("--impostors", o.draw.allImpostors,
                                 "every instance that has an impostor draws as one, at any "
                                 "distance");
  naive->excludes(geometry, impostors);
  geometry->excludes(impostors);
  app.add_flag("--whole-body", o.draw.wholeBody,
               "clothed packs: draw the whole body under the garments (the naive method, for "
               "comparison) instead of each outfit's visible sub-meshes");
  app.add_option_function<std::string>(
         "--skinning", [&o](const std::string &how) { o.draw.trackSkinning = how == "tracks"; },
         "texture: joints from the animation texture where a pack stores one; tracks: packs with "
         "joint tracks (crowdbake anim --store tracks|both) skin from palettes a compute pass "
         "decodes each frame. Packs of joint tracks alone skin from palettes either way")
      ->check(CLI::IsMember({"texture", "tracks"}))
      ->default_str("texture");
  app.add_option("--palette-slot", o.paletteSlot,
                 "instances whose clip times fall in one slot share a palette (joint tracks): "
                 "'clip' (each clip's own sample step) or seconds, 0 for exact times; "
                 "overrides the scene's \"palette_slot\"")
      ->check([](const std::string &v) {
        char *end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        const double most = crowd::runtime::kMaxPaletteSlot;
        return v == "clip" || (!v.empty() && *end == 0 && x >= 0 && x <= most)
                   ? std::string()
                   : "'clip' or seconds in 0.." + std::to_string(int(most));
      })
      ->default_str("the scene's, else clip");
  app.add_option("--clip", o.clip, "pack previews: show this clip only");
  app.add_option("--outfit", o.outfit, "pack previews: show this outfit only");
  app.add_option("--time", o.startTime, "scene time of the first frame, in seconds")
      ->capture_default_str();
  app.add_option("--step", o.step, "headless time step between frames, in seconds")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  app.footer("\nexamples:\n  crowdplay samples/scenes/demo.json --headless --frames "
             "120 --screenshot a.png --stats s.json\n  crowdplay out/library/humanoid.crowdpack "
             "--clip walk --outfit dress\n");
  app.set_version_flag("--version",
                       std::string("crowdplay ") + crowd::kVersion + "\n" +
                           crowd::pack::formatVersions(),
                       "the version and the pack and chunk versions it reads");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp &) {
    std::cout << app.help();
    return false;
  } catch (const CLI::CallForVersion &e) {
    std::cout << e.what() << "\n";
    return false;
  } catch (const CLI::ParseError &e) {
    throw UsageError(std::string(e.what()) + " (see crowdplay --help)");
  }
  if (!std::isfinite(o.startTime))
    throw UsageError("--time: expects finite seconds");
  const auto x = size.find('x');
  auto side = [&](const std::string &v) {
    int n = 0;
    auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
    if (ec != std::errc() || end != v.data() + v.size() || n < 16 ||
        n > int(crowd::limits::kScreenSide))
      throw UsageError("--size expects WxH, each in [16, " +
                       std::to_string(crowd::limits::kScreenSide) + "], got '" + size + "'");
    return n;
  };
  if (x == std::string::npos)
    throw UsageError("--size expects WxH, got '" + size + "'");
  o.width = side(size.substr(0, x));
  o.height = side(size.substr(x + 1));
  if (!o.previewPack() && !(o.clip.empty() && o.outfit.empty()))
    throw UsageError("--clip and --outfit preview a pack (a .crowdpack), not a scene");
  if (o.previewPack() && o.instances)
    throw UsageError("--instances changes a scene's count; a pack preview has one per pair");
  return true;
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
  crowd::pack::Image image{"", uint32_t(w), uint32_t(h), 3, crowd::pack::Image::Pixel::U8, {}};
  std::vector<uint8_t> &rgb = image.bytes;
  rgb.resize(size_t(w) * size_t(h) * 3);
  for (int y = 0; y < h; ++y) // GL rows start at the bottom
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < 3; ++k)
        rgb[(size_t(y) * size_t(w) + size_t(x)) * 3 + size_t(k)] =
            rgba[(size_t(h - 1 - y) * size_t(w) + size_t(x)) * 4 + size_t(k)];
  crowd::images::write(path, image);
}

struct Glfw {
  // `before`: why a headless run found no display-less context, for the error.
  explicit Glfw(const std::string &before) {
    if (!glfwInit()) {
      const char *why = nullptr;
      glfwGetError(&why);
      throw crowd::Error(before + "cannot initialise GLFW: " + (why ? why : "no reason given") +
                         " (no display? run under xvfb-run -a)");
    }
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
  glNamedRenderbufferStorage(depth, GL_DEPTH24_STENCIL8, o.width, o.height); // stencil: shadows
  glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
  glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth);
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
  double sums[9] = {}, agentsMs = 0, palettes = 0, paletteMs = 0, paletteGpuMs = 0;
  crowd::runtime::DrawOptions draw = o.draw;
  draw.timePalettes = !o.stats.empty(); // where a palette pass runs
  for (int f = 0; f < o.frames; ++f) {
    double t = o.startTime + f * o.step;
    auto t0 = std::chrono::steady_clock::now();
    glClearColor(0.55f, 0.62f, 0.70f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glBeginQuery(GL_TIME_ELAPSED, query);
    if (vertexQuery)
      glBeginQuery(GL_VERTEX_SHADER_INVOCATIONS_ARB, vertexQuery);
    auto stats = renderer.draw(frameView(scene.camera, t, o.width, o.height), float(t), draw);
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
    agentsMs += stats.agentsMs;
    palettes += stats.palettes, paletteMs += stats.paletteMs, paletteGpuMs += stats.paletteGpuMs;
    frames.push_back(row);
  }
  if (!o.screenshot.empty()) {
    std::vector<uint8_t> rgba(size_t(o.width) * size_t(o.height) * 4);
    glReadPixels(0, 0, o.width, o.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    writePng(o.screenshot, o.width, o.height, rgba);
  }
  nlohmann::ordered_json summary;
  summary["frames"] = o.frames;
  if (scene.world.enabled()) // the agents' steps up to each frame and their placing, CPU
    summary["agents_ms"] = agentsMs / o.frames;
  for (int k = 0; k < columns; ++k)
    summary[keys[k]] = sums[k] / o.frames;
  summary["skinning"] = o.draw.trackSkinning ? "tracks" : "texture";
  if (o.draw.trackSkinning ||
      palettes > 0) { // per frame: palettes decoded, their CPU and GPU milliseconds
    summary["palettes"] = palettes / o.frames;
    summary["palette_slot"] = scene.paletteSlot < 0 ? nlohmann::ordered_json("clip")
                                                    : nlohmann::ordered_json(scene.paletteSlot);
    summary["palette_cpu_ms"] = paletteMs / o.frames;
    summary["palette_gpu_ms"] = paletteGpuMs / o.frames;
  }
  summary["whole_body"] = o.draw.wholeBody;
  summary["budget"] = o.draw.budget;
  summary["detail"] = o.draw.detail; // 0: chosen under the budget
  summary["all_impostors"] = o.draw.allImpostors;
  summary["impostor_gpu_bytes"] = renderer.impostorBytes(); // every frame and mip level
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

// The packs a scene draws, loaded once, and a renderer over them for a scene: a preview makes a
// new one when its choice of clip or outfit changes the instances.
struct Crowd {
  std::vector<crowd::pack::CharacterPack> packs;
  std::vector<crowd::pack::ImpostorPack> impostorPacks;
  std::vector<const crowd::pack::Impostor *> impostors; // per pack, null for none

  std::unique_ptr<crowd::runtime::SceneWorld> world; // the scene's "world", if any

  std::unique_ptr<crowd::runtime::CrowdRenderer> renderer(crowd::runtime::Scene scene) const {
    auto types = crowd::runtime::characterTypes(scene, packs, impostors);
    auto r = std::make_unique<crowd::runtime::CrowdRenderer>(types.packs, types.impostors, scene,
                                                             types.cloths);
    if (world)
      r->attachWorld(*world);
    return r;
  }
};

// An image of a scene's world as RGBA8 rows (the first row at the terrain's lowest z); none
// for an empty path.
crowd::runtime::RgbaImage readRgba(const std::string &path) {
  crowd::runtime::RgbaImage image;
  if (path.empty())
    return image;
  const std::vector<uint8_t> bytes =
      crowd::readRegularFile(path, {crowd::limits::kInputFileBytes, ""});
  crowd::pack::Image decoded;
  std::string why;
  const int side = int(crowd::limits::kScreenSide);
  if (!crowd::images::decode(bytes, path, side, decoded, why) || decoded.channels < 3)
    throw crowd::Error(path + ": expected an RGB or RGBA image of at most " + std::to_string(side) +
                       " pixels a side" + (why.empty() ? "" : ": " + why));
  const size_t c = decoded.channels;
  image.width = decoded.width, image.height = decoded.height;
  for (size_t i = 0; i < size_t(image.width) * image.height; ++i)
    for (size_t k = 0; k < 4; ++k)
      image.rgba.push_back(k < c ? decoded.bytes[i * c + k] : uint8_t(255));
  return image;
}

// The scene's world: its terrain pack and images, and the agents over them.
std::unique_ptr<crowd::runtime::SceneWorld> loadWorld(const crowd::runtime::Scene &scene) {
  const auto &w = scene.world;
  if (!std::filesystem::exists(w.terrainPath))
    throw crowd::Error(scene.path + ": terrain pack '" + w.terrainPath +
                       "' does not exist (bake it: crowdbake terrain)");
  const auto reader = crowd::pack::Reader::open(w.terrainPath);
  const auto *chunk = reader.find(crowd::pack::kTerrain);
  if (!chunk)
    throw crowd::Error(w.terrainPath + ": holds no terrain (bake it with crowdbake terrain)");
  auto world = std::make_unique<crowd::runtime::SceneWorld>(
      scene,
      crowd::pack::decodeTerrain(
          reader.payload(*chunk),
          crowd::pack::chunkContext(reader, size_t(chunk - reader.chunks().data()))),
      readRgba(w.behaviourPath), readRgba(w.callbackPath));
  if (const uint32_t moved = world->crowd().figures().spawnedMoved)
    std::fprintf(stderr,
                 "crowdplay: %u agents spawned where they cannot stand (a building, a taken "
                 "cell) were moved to the nearest free walkable cell\n",
                 moved);
  return world;
}

// A pack preview's clip or outfit by name (-1 for ""); an error lists the names there are.
int pick(const std::vector<std::string> &names, const std::string &name, const char *what) {
  if (name.empty())
    return -1;
  std::string all;
  for (size_t k = 0; k < names.size(); ++k) {
    if (names[k] == name)
      return int(k);
    all += (k ? ", " : "") + names[k];
  }
  throw crowd::Error(std::string("the pack has no ") + what + " '" + name + "' (" + what +
                     "s: " + all + ")");
}

// The window's keys: L steps the fixed level of detail, I the drawing path.
constexpr double kDetails[] = {0, 1, 0.5, 0.25, 0.1, 0.05};

void nextDetail(crowd::runtime::DrawOptions &d) {
  size_t k = 0;
  while (k < std::size(kDetails) && kDetails[k] != d.detail)
    ++k;
  d.detail = kDetails[(k + 1) % std::size(kDetails)]; // from a value off the list: auto
}

void nextDrawing(crowd::runtime::DrawOptions &d) {
  using crowd::runtime::DrawPath;
  if (d.path == DrawPath::Hybrid && !d.allImpostors)
    d.path = DrawPath::Instanced;
  else if (d.path == DrawPath::Instanced)
    d.path = DrawPath::Hybrid, d.allImpostors = true;
  else
    d.path = DrawPath::Hybrid, d.allImpostors = false;
}

std::string drawingText(const crowd::runtime::DrawOptions &d) {
  char lod[32] = "LOD auto";
  if (d.detail > 0)
    std::snprintf(lod, sizeof lod, "LOD %g%%", 100 * d.detail);
  const char *drawing = d.allImpostors                                  ? "impostors only"
                        : d.path == crowd::runtime::DrawPath::Instanced ? "geometry only"
                                                                        : pathName(d.path);
  return std::string(lod) + "  " + drawing;
}

std::string previewText(const crowd::runtime::Scene &s, const crowd::runtime::PreviewChoice &c) {
  auto name = [](const std::vector<std::string> &names, int k) {
    return k < 0 ? std::string("all") : names[size_t(k)].empty() ? "-" : names[size_t(k)];
  };
  return "clip " + name(s.clipNames, c.clip) + "  outfit " + name(s.outfitNames, c.outfit) + "  ";
}

struct Orbit {
  double yaw = 0, pitch = 0, distance = 1, lastX = 0, lastY = 0;
  glm::dvec3 pan{0};
  bool dragging = false;
  std::vector<int> pressed; // keys pressed since the last frame
};

// `preview` (empty for a scene file) makes the preview scene of a choice of clip and outfit.
using PreviewFn = std::function<crowd::runtime::Scene(const crowd::runtime::PreviewChoice &)>;

int interactive(GLFWwindow *win, Options o, const Crowd &crowd, crowd::runtime::Scene scene,
                crowd::runtime::PreviewChoice choice, const PreviewFn &preview) {
  auto renderer = crowd.renderer(scene);
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
  // Key presses are events, not polled states: a tap shorter than a frame still counts.
  glfwSetKeyCallback(win, [](GLFWwindow *w, int key, int, int action, int) {
    if (action == GLFW_PRESS && key == GLFW_KEY_ESCAPE)
      glfwSetWindowShouldClose(w, 1);
    else if (action == GLFW_PRESS)
      static_cast<Orbit *>(glfwGetWindowUserPointer(w))->pressed.push_back(key);
  });
  glEnable(GL_DEPTH_TEST);
  auto start = std::chrono::steady_clock::now(), lastTitle = start;
  double frameMs = 0;
  bool userCamera = false;
  auto previewShown = choice; // the choice the scene shows
  while (!glfwWindowShouldClose(win)) {
    auto t0 = std::chrono::steady_clock::now();
    double t = o.startTime + std::chrono::duration<double>(t0 - start).count();
    bool rebuild = false;
    auto next = [](int k, size_t n) { return k + 1 < int(n) ? k + 1 : -1; }; // then all again
    for (int key : std::exchange(orbit.pressed, {})) {
      if (key == GLFW_KEY_C && preview)
        choice.clip = next(choice.clip, scene.clipNames.size()), rebuild = true;
      else if (key == GLFW_KEY_O && preview)
        choice.outfit = next(choice.outfit, scene.outfitNames.size()), rebuild = true;
      else if (key == GLFW_KEY_L)
        nextDetail(o.draw);
      else if (key == GLFW_KEY_I)
        nextDrawing(o.draw);
      lastTitle = {}; // show the choice now
    }
    if (rebuild) {
      auto camera = scene.camera;
      const auto shown = std::exchange(previewShown, choice);
      scene = preview(choice);
      crowd::runtime::crossfadeFrom(scene, shown, choice, t);
      if (userCamera)
        scene.camera = camera;
      renderer = crowd.renderer(scene);
    }
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
    auto stats = renderer->draw(frameView(scene.camera, t, w, h), float(t), o.draw);
    glfwSwapBuffers(win);
    glfwPollEvents();
    auto t1 = std::chrono::steady_clock::now();
    frameMs = 0.9 * frameMs + 0.1 * std::chrono::duration<double, std::milli>(t1 - t0).count();
    if (t1 - lastTitle > std::chrono::milliseconds(500)) {
      char figures[256];
      std::snprintf(figures, sizeof figures,
                    "  |  %.1f ms  %u of %u visible (%u impostors)  %.1f k triangles (%s)  "
                    "%u draw calls  cull + select %.2f ms",
                    frameMs, stats.visible, stats.instances, stats.impostors,
                    double(stats.triangles) / 1e3, budgetText(o.draw.budget).c_str(),
                    stats.drawCalls, stats.cullSelectMs);
      const std::string title = "crowdplay  " + scene.packNames[0] + "  " +
                                (preview ? previewText(scene, choice) : "") + drawingText(o.draw) +
                                figures;
      glfwSetWindowTitle(win, title.c_str());
      lastTitle = t1;
    }
  }
  return 0;
}

// --palette-slot over the scene's.
void overrideSlot(const Options &o, crowd::runtime::Scene &scene) {
  if (!o.paletteSlot.empty())
    scene.paletteSlot =
        o.paletteSlot == "clip" ? crowd::runtime::kClipSampleSlot : std::stof(o.paletteSlot);
}

} // namespace

int main(int argc, char **argv) {
  try {
    Options o;
    if (!parse(argc, argv, o))
      return 0;
    Crowd crowd;
    crowd::runtime::Scene scene;
    crowd::runtime::PreviewChoice choice;
    PreviewFn preview;
    if (o.previewPack()) { // a pack without a scene file: the preview of its clips and outfits
      crowd.packs.push_back(crowd::pack::loadCharacterPack(crowd::pack::Reader::open(o.scene)));
      crowd.impostors = {nullptr};
      preview = [&](const crowd::runtime::PreviewChoice &c) {
        crowd::runtime::Scene s = crowd::runtime::previewScene(o.scene, crowd.packs[0], c);
        overrideSlot(o, s);
        return s;
      };
      const auto all = preview({});
      choice = {pick(all.clipNames, o.clip, "clip"), pick(all.outfitNames, o.outfit, "outfit")};
      scene = preview(choice);
    } else {
      scene = crowd::runtime::loadScene(o.scene, o.instances);
      overrideSlot(o, scene);
      for (const auto &path : scene.packPaths) {
        if (!std::filesystem::exists(path))
          throw crowd::Error(o.scene + ": pack '" + path +
                             "' does not exist (bake it first: ./run demo)");
        crowd.packs.push_back(crowd::pack::loadCharacterPack(crowd::pack::Reader::open(path)));
      }
      crowd.impostorPacks.resize(scene.impostorPaths.size());
      crowd.impostors.assign(scene.impostorPaths.size(), nullptr);
      for (size_t k = 0; k < scene.impostorPaths.size(); ++k) {
        const std::string &path = scene.impostorPaths[k];
        if (path.empty())
          continue;
        if (!std::filesystem::exists(path))
          throw crowd::Error(o.scene + ": impostor pack '" + path +
                             "' does not exist (bake it: crowdbake impostor)");
        crowd.impostorPacks[k] = crowd::pack::loadImpostorPack(crowd::pack::Reader::open(path));
        crowd.impostors[k] = &crowd.impostorPacks[k].impostor;
      }
    }
    if (scene.world.enabled())
      crowd.world = loadWorld(scene);
    o.draw.budget = o.budget >= 0 ? uint64_t(o.budget) : scene.budget;
    std::string eglWhy; // headless: EGL first (a GPU or Mesa without a display), else a window
    if (o.headless)
      if (auto gl = crowd::runtime::HeadlessGl::open(eglWhy))
        return headless(o, *crowd.renderer(scene), scene);
    Glfw glfw(o.headless ? "no EGL context (" + eglWhy + "), and " : "");
    GLFWwindow *win =
        openWindow(o.headless ? 64 : o.width, o.headless ? 64 : o.height, !o.headless);
    if (o.headless)
      return headless(o, *crowd.renderer(scene), scene);
    return interactive(win, o, crowd, scene, choice, preview);
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
