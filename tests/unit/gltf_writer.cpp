#include "gltf_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "crowd/bake/glb.h"

namespace crowd::test {

namespace {
std::string base64(const std::vector<uint8_t> &in) {
  static const char *k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < in.size(); i += 3) {
    uint32_t v = uint32_t(in[i]) << 16 | (i + 1 < in.size() ? uint32_t(in[i + 1]) << 8 : 0) |
                 (i + 2 < in.size() ? in[i + 2] : 0);
    out += k[v >> 18 & 63];
    out += k[v >> 12 & 63];
    out += i + 1 < in.size() ? k[v >> 6 & 63] : '=';
    out += i + 2 < in.size() ? k[v & 63] : '=';
  }
  return out;
}
} // namespace

GltfBuilder::GltfBuilder() {
  j["asset"] = {{"version", "2.0"}};
  j["scene"] = 0;
  j["scenes"] = nlohmann::json::array({{{"nodes", nlohmann::json::array()}}});
  j["nodes"] = nlohmann::json::array();
  j["accessors"] = nlohmann::json::array();
  j["bufferViews"] = nlohmann::json::array();
}

int GltfBuilder::addAccessor(size_t offset, size_t bytes, int componentType,
                             const std::string &type, bool normalized) {
  j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
  size_t comps = type == "SCALAR" ? 1
                 : type == "VEC2" ? 2
                 : type == "VEC3" ? 3
                 : type == "VEC4" ? 4
                                  : 16;
  size_t cs = componentType == 5126 || componentType == 5125 ? 4 : componentType >= 5122 ? 2 : 1;
  nlohmann::json a = {{"bufferView", j["bufferViews"].size() - 1},
                      {"componentType", componentType},
                      {"count", bytes / (comps * cs)},
                      {"type", type}};
  if (normalized)
    a["normalized"] = true;
  j["accessors"].push_back(a);
  return int(j["accessors"].size() - 1);
}

int GltfBuilder::skinnedQuad() {
  int pos = floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, "VEC3");
  j["accessors"][size_t(pos)]["min"] = {0, 0, 0};
  j["accessors"][size_t(pos)]["max"] = {1, 1, 0};
  int joints =
      accessor(std::vector<uint8_t>{0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, 5121, "VEC4");
  int weights = floats({1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 0.25f, 0.75f, 0, 0}, "VEC4");
  int idx = accessor(std::vector<uint16_t>{0, 1, 2, 2, 1, 3}, 5123, "SCALAR");
  int ibm = floats({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0,     0, 1,
                    1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -0.5f, 0, 1},
                   "MAT4");
  nlohmann::json prim = {
      {"attributes", {{"POSITION", pos}, {"JOINTS_0", joints}, {"WEIGHTS_0", weights}}},
      {"indices", idx}};
  j["meshes"] = nlohmann::json::array();
  j["meshes"].push_back({{"name", "quad"}, {"primitives", nlohmann::json::array({prim})}});
  size_t base = j["nodes"].size();
  j["nodes"].push_back({{"name", "a"}, {"children", {base + 1}}});
  j["nodes"].push_back({{"name", "b"}, {"translation", {0, 0.5, 0}}});
  j["nodes"].push_back({{"name", "quad"}, {"mesh", 0}, {"skin", 0}});
  j["skins"] = {{{"joints", {base, base + 1}}, {"inverseBindMatrices", ibm}}};
  j["scenes"][0]["nodes"].push_back(base);
  j["scenes"][0]["nodes"].push_back(base + 2);
  return int(base + 2);
}

void GltfBuilder::morphTargets(int mesh, const std::vector<std::vector<float>> &offsets) {
  auto &prim = j["meshes"][size_t(mesh)]["primitives"][0];
  prim["targets"] = nlohmann::json::array();
  for (const auto &target : offsets) {
    const int acc = floats(target, "VEC3");
    std::vector<float> lo(3, INFINITY), hi(3, -INFINITY);
    for (size_t k = 0; k < target.size(); ++k)
      lo[k % 3] = std::min(lo[k % 3], target[k]), hi[k % 3] = std::max(hi[k % 3], target[k]);
    j["accessors"][size_t(acc)]["min"] = lo;
    j["accessors"][size_t(acc)]["max"] = hi;
    prim["targets"].push_back({{"POSITION", acc}});
  }
  j["meshes"][size_t(mesh)]["weights"] = std::vector<float>(offsets.size(), 0.0f);
}

int GltfBuilder::morphedQuad(int targets) {
  const int node = skinnedQuad();
  std::vector<std::vector<float>> offsets;
  for (int t = 0; t < targets; ++t) {
    offsets.push_back(std::vector<float>(12, 0.0f));
    offsets.back()[10] = 0.01f * float(t + 1);
  }
  morphTargets(0, offsets);
  const int anim = animation("wave", 1, "rotation", {0, 1, 2},
                             {0, 0, 0, 1, 0, 0, 0.70710678f, 0.70710678f, 0, 0, 0, 1});
  std::vector<float> weights;
  for (float w : {0.0f, 1.0f, 0.0f})
    weights.insert(weights.end(), size_t(targets), w);
  channel(anim, node, "weights", {0, 1, 2}, weights);
  return node;
}

int GltfBuilder::animation(const std::string &name, int node, const std::string &path,
                           const std::vector<float> &times, const std::vector<float> &values,
                           const std::string &interpolation) {
  j["animations"].push_back({{"name", name},
                             {"samplers", nlohmann::json::array()},
                             {"channels", nlohmann::json::array()}});
  const int anim = int(j["animations"].size() - 1);
  channel(anim, node, path, times, values, interpolation);
  return anim;
}

void GltfBuilder::channel(int anim, int node, const std::string &path,
                          const std::vector<float> &times, const std::vector<float> &values,
                          const std::string &interpolation) {
  int in = floats(times, "SCALAR");
  j["accessors"][size_t(in)]["min"] = {times.front()};
  j["accessors"][size_t(in)]["max"] = {times.back()};
  int out = floats(values, path == "rotation" ? "VEC4" : path == "weights" ? "SCALAR" : "VEC3");
  auto &a = j["animations"][size_t(anim)];
  a["samplers"].push_back({{"input", in}, {"output", out}, {"interpolation", interpolation}});
  a["channels"].push_back(
      {{"sampler", a["samplers"].size() - 1}, {"target", {{"node", node}, {"path", path}}}});
}

std::string GltfBuilder::write(const std::string &dir, const std::string &name,
                               bool external) const {
  nlohmann::json out = j;
  std::vector<uint8_t> data = bin;
  while (data.size() % 4)
    data.push_back(0);
  if (external) {
    std::ofstream(dir + "/" + name + ".bin", std::ios::binary)
        .write(reinterpret_cast<const char *>(data.data()), std::streamsize(data.size()));
    out["buffers"] = {{{"byteLength", data.size()}, {"uri", name + ".bin"}}};
  } else {
    out["buffers"] = {{{"byteLength", data.size()},
                       {"uri", "data:application/octet-stream;base64," + base64(data)}}};
  }
  std::string path = dir + "/" + name + ".gltf";
  std::ofstream(path) << out.dump();
  return path;
}

std::string GltfBuilder::writeGlb(const std::string &dir, const std::string &name) const {
  nlohmann::json out = j;
  std::vector<uint8_t> data = bin;
  while (data.size() % 4)
    data.push_back(0);
  out["buffers"] = {{{"byteLength", data.size()}}};
  const std::vector<uint8_t> glb = glbBytes(out, data);
  std::string path = dir + "/" + name + ".glb";
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char *>(glb.data()), std::streamsize(glb.size()));
  return path;
}

std::string tempDir(const std::string &name) {
  // Removed when the test program exits, unless CROWD_KEEP_TEST_FILES is set (to look at them).
  static struct Cleanup {
    std::vector<std::filesystem::path> dirs;
    ~Cleanup() {
      if (!std::getenv("CROWD_KEEP_TEST_FILES"))
        for (const auto &d : dirs) {
          std::error_code ignored;
          std::filesystem::remove_all(d, ignored);
        }
    }
  } cleanup;
  auto dir = std::filesystem::temp_directory_path() /
             ("crowd_test_" + name + "_" + std::to_string(::getpid()));
  cleanup.dirs.push_back(dir);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

} // namespace crowd::test
