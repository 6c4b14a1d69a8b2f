// Test helper: builds small glTF files by hand (JSON + one data-URI or external buffer) so tests
// can state exactly what a file holds, including the malformed ones.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace crowd::test {

struct GltfBuilder {
  nlohmann::json j;
  std::vector<uint8_t> bin;

  GltfBuilder();
  // Appends raw values as a bufferView + accessor; returns the accessor index.
  template <class T>
  int accessor(const std::vector<T> &values, int componentType, const std::string &type,
               bool normalized = false) {
    while (bin.size() % 4)
      bin.push_back(0);
    size_t offset = bin.size();
    bin.resize(offset + values.size() * sizeof(T));
    std::memcpy(bin.data() + offset, values.data(), values.size() * sizeof(T));
    return addAccessor(offset, values.size() * sizeof(T), componentType, type, normalized);
  }
  int floats(const std::vector<float> &v, const std::string &type) {
    return accessor(v, 5126, type);
  }

  // A skinned two-joint strip of two triangles (4 vertices) bound to joints "a" and "b", with
  // node "b" a child of "a". Returns the mesh node.
  int skinnedQuad();
  // Gives primitive 0 of mesh `mesh` one morph target per entry of `offsets` (POSITION offsets,
  // xyz per vertex) with default weights 0.
  void morphTargets(int mesh, const std::vector<std::vector<float>> &offsets);
  // The skinned quad with `targets` morph targets, target t moving vertex 3 up by (t + 1) cm, and
  // clip "wave": joint "b" turns 90 degrees about z while every weight goes 0 -> 1 -> 0 over 2 s.
  // Returns the mesh node.
  int morphedQuad(int targets);
  // Adds an animation with one channel and returns its index ("weights": one value per target
  // per key).
  int animation(const std::string &name, int node, const std::string &path,
                const std::vector<float> &times, const std::vector<float> &values,
                const std::string &interpolation = "LINEAR");
  // Adds a channel to animation `anim`.
  void channel(int anim, int node, const std::string &path, const std::vector<float> &times,
               const std::vector<float> &values, const std::string &interpolation = "LINEAR");

  // Writes NAME.gltf (data-URI buffer) or, with external, NAME.gltf + NAME.bin.
  std::string write(const std::string &dir, const std::string &name, bool external = false) const;
  // Writes NAME.glb.
  std::string writeGlb(const std::string &dir, const std::string &name) const;

private:
  int addAccessor(size_t offset, size_t bytes, int componentType, const std::string &type,
                  bool normalized);
};

// A fresh folder for one test, removed at exit (kept when CROWD_KEEP_TEST_FILES is set).
std::string tempDir(const std::string &name);

} // namespace crowd::test
