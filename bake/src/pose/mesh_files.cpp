#include "crowd/bake/mesh_files.h"

#include <cmath>
#include <cstdio>
#include <cstring>

#include <nlohmann/json.hpp>

#include "crowd/bake/glb.h"

namespace crowd {

namespace {

void append(std::vector<uint8_t> &out, const std::string &text) {
  out.insert(out.end(), text.begin(), text.end());
}

template <class T> void put(std::vector<uint8_t> &out, T value) { // little-endian hosts only
  const size_t at = out.size();
  out.resize(at + sizeof(T));
  std::memcpy(out.data() + at, &value, sizeof(T));
}

std::string line(const char *format, double a, double b, double c) {
  char buf[128];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

} // namespace

std::vector<uint8_t> plyBytes(const std::vector<glm::vec3> &p, const std::vector<glm::vec3> &n,
                              const std::vector<uint32_t> &indices,
                              const std::vector<pack::VertexSource> &sources, bool ascii) {
  std::vector<uint8_t> out;
  append(out, "ply\nformat ");
  append(out, ascii ? "ascii" : "binary_little_endian");
  append(out, " 1.0\ncomment crowdbake pose\nelement vertex ");
  append(out, std::to_string(p.size()));
  append(out, "\nproperty float x\nproperty float y\nproperty float z\n"
              "property float nx\nproperty float ny\nproperty float nz\n"
              "property int source_file\nproperty int source_node\nproperty int source_mesh\n"
              "property int source_primitive\nproperty int source_vertex\nelement face ");
  append(out, std::to_string(indices.size() / 3));
  append(out, "\nproperty list uchar uint vertex_indices\nend_header\n");
  for (size_t v = 0; v < p.size(); ++v) {
    const pack::VertexSource s = v < sources.size() ? sources[v] : pack::VertexSource{};
    if (ascii) {
      append(out, line("%.9g %.9g %.9g ", p[v].x, p[v].y, p[v].z));
      append(out, line("%.9g %.9g %.9g", n[v].x, n[v].y, n[v].z));
      for (int32_t i : {s.file, s.node, s.mesh, s.primitive, s.vertex}) {
        append(out, " ");
        append(out, std::to_string(i));
      }
      append(out, "\n");
      continue;
    }
    for (float f : {p[v].x, p[v].y, p[v].z, n[v].x, n[v].y, n[v].z})
      put(out, f);
    for (int32_t i : {s.file, s.node, s.mesh, s.primitive, s.vertex})
      put(out, i);
  }
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    if (ascii) {
      append(out, line("3 %.0f %.0f %.0f\n", indices[t], indices[t + 1], indices[t + 2]));
      continue;
    }
    put(out, uint8_t(3));
    for (int k = 0; k < 3; ++k)
      put(out, indices[t + k]);
  }
  return out;
}

std::vector<uint8_t> objBytes(const std::vector<glm::vec3> &p, const std::vector<glm::vec3> &n,
                              const std::vector<uint32_t> &indices) {
  std::vector<uint8_t> out;
  append(out, "# crowdbake pose\n");
  for (const auto &v : p)
    append(out, line("v %.9g %.9g %.9g\n", v.x, v.y, v.z));
  for (const auto &v : n)
    append(out, line("vn %.9g %.9g %.9g\n", v.x, v.y, v.z));
  for (size_t t = 0; t + 2 < indices.size(); t += 3) { // OBJ counts from 1
    const double a = indices[t] + 1.0, b = indices[t + 1] + 1.0, c = indices[t + 2] + 1.0;
    char f[128];
    std::snprintf(f, sizeof f, "f %.0f//%.0f %.0f//%.0f %.0f//%.0f\n", a, a, b, b, c, c);
    append(out, f);
  }
  return out;
}

std::vector<uint8_t> glbBytes(const std::vector<glm::vec3> &p, const std::vector<glm::vec3> &n,
                              const std::vector<uint32_t> &indices) {
  // One buffer: positions, unit normals (glTF requires them; a zero normal becomes +y), indices.
  std::vector<uint8_t> bin;
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (const auto &v : p) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
    for (float f : {v.x, v.y, v.z})
      put(bin, f);
  }
  for (const auto &v : n) {
    const float length = glm::length(v);
    const glm::vec3 unit =
        length > 1e-20f && std::isfinite(length) ? v / length : glm::vec3(0, 1, 0);
    for (float f : {unit.x, unit.y, unit.z})
      put(bin, f);
  }
  for (uint32_t i : indices)
    put(bin, i);
  const size_t vertexBytes = p.size() * 12;
  using nlohmann::json;
  auto view = [](size_t offset, size_t length, int target) {
    return json{{"buffer", 0}, {"byteOffset", offset}, {"byteLength", length}, {"target", target}};
  };
  const json gltf = {
      {"asset", {{"version", "2.0"}, {"generator", "crowdbake pose"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"meshes",
       {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}, {"indices", 2}}}}}}},
      {"buffers", {{{"byteLength", bin.size()}}}},
      {"bufferViews",
       {view(0, vertexBytes, 34962), view(vertexBytes, vertexBytes, 34962),
        view(2 * vertexBytes, indices.size() * 4, 34963)}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5126},
         {"count", p.size()},
         {"type", "VEC3"},
         {"min", {lo.x, lo.y, lo.z}},
         {"max", {hi.x, hi.y, hi.z}}},
        {{"bufferView", 1}, {"componentType", 5126}, {"count", n.size()}, {"type", "VEC3"}},
        {{"bufferView", 2},
         {"componentType", 5125},
         {"count", indices.size()},
         {"type", "SCALAR"}}}}};
  return glbBytes(gltf, bin);
}

} // namespace crowd
