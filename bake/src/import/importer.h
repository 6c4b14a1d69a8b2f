// importGltf's stages over one file, each in its own file: load (gltf_import.cpp: the file, its
// compressed views, tinygltf's parse), accessors (gltf_accessors.h, a class of its own), the node
// hierarchy and the choice of skins and mesh nodes (gltf_nodes.cpp), meshes (gltf_meshes.cpp) and
// their morph targets (gltf_morphs.cpp), animations (gltf_animations.cpp, a sampler's keys in
// gltf_animations.h) and the diffuse texture (gltf_textures.cpp). Every error names the file and
// what in it is wrong.
#pragma once
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "crowd/bake/import.h"
#include "crowd/formats/error.h"
#include "gltf_accessors.h"
#include "unique_names.h"

namespace crowd::gltf {

// Images are kept encoded as tinygltf hands them over; only the diffuse texture the mesh uses is
// decoded, and an image that cannot be decoded is a warning, not a failure.
using EncodedImages = std::map<int, std::vector<uint8_t>>;

class Importer {
public:
  Importer(std::string path, Reporter &reporter) : path_(std::move(path)), reporter_(reporter) {}
  Character run(const ImportOptions &options);

private:
  struct MeshNode {
    int node;
    int rigid; // node that acts as the joint of a rigid mesh, or -1 when skinned
    uint16_t rigidJoint = 0;
    int skin = -1; // a skinned mesh's skin
  };
  // readMeshes' state across primitives: the sub-meshes by name as they first come, the vertex
  // sets read, and what was repaired or skipped, for its warnings.
  struct MeshState {
    std::vector<std::string> partOrder;
    std::vector<std::vector<uint32_t>> partTriangles;
    std::vector<SkinnedMesh::Part> partLooks;
    std::map<std::string, uint32_t> vertexBases; // first vertex of each distinct vertex set
    std::set<std::string> seenPrimitives;
    size_t moreThan4 = 0, renormalised = 0, missingNormals = 0, duplicatePrimitives = 0,
           pointsOrLines = 0, unweighted = 0, mirroredPrimitives = 0;
  };
  using Influences = std::vector<std::vector<std::pair<double, int>>>; // per vertex: weight, entry

  [[noreturn]] void fail(const std::string &what) const { throw Error(path_ + ": " + what); }
  // A warning under `code` that starts with how many (`count` things `what`), where any were.
  void warnCount(const std::string &code, size_t count, const std::string &what) {
    if (count)
      reporter_.warn(code, std::to_string(count) + " " + what, count);
  }
  // Renames what repeats an earlier name in `items` (unique_names.h), saying so under `code`.
  template <class T>
  void makeNamesUnique(std::vector<T> &items, const std::string &code, const std::string &what,
                       const std::string &why) {
    std::vector<std::string *> names;
    for (T &item : items)
      names.push_back(&item.name);
    warnCount(code, makeUnique(names),
              what + " repeat an earlier one's name: renamed NAME_2, NAME_3, ... (" + why + ")");
  }

  // gltf_import.cpp
  void load(const InputPolicy &policy);

  // gltf_nodes.cpp
  void buildHierarchy();
  // Whether the node's rest transform, with its ancestors', mirrors (a negative determinant).
  bool mirrors(int node) const;
  bool hasAncestorIn(int node, const std::set<int> &set) const;
  void selectMeshes(const ImportOptions &options);
  void chooseSkins(const ImportOptions &options);
  std::set<int> mergeSkinJoints();
  void chooseMeshNodes(const ImportOptions &options, const std::set<int> &jointSet);
  void orderJoints();

  // gltf_meshes.cpp
  // That accessor `acc` (attribute `name` of `ctx`) is of `type` with `count` elements.
  void checkLikePosition(int acc, const std::string &ctx, const std::string &name, int type,
                         size_t count) const;
  void readMeshes();
  void readPrimitive(const MeshNode &mn, size_t pi, bool mirrored, MeshState &state);
  std::vector<uint32_t> readIndices(const tinygltf::Primitive &prim, const std::string &ctx,
                                    size_t vc);
  Influences readInfluences(const tinygltf::Primitive &prim, const MeshNode &mn,
                            const std::string &ctx, size_t vc, const std::vector<double> &pos,
                            MeshState &state);
  // The primitive's vertices appended to the mesh, each with its 4 largest influences.
  void appendVertices(const MeshNode &mn, size_t pi, const std::string &ctx, size_t vc,
                      const std::vector<double> &pos, const std::vector<double> &nrm,
                      const std::vector<double> &uv, Influences &infl, MeshState &state);
  // The sub-mesh of the primitive's material, made with its look where it is the first.
  size_t partOf(const tinygltf::Primitive &prim, bool hasUv, MeshState &state);
  void warnMeshRepairs(const MeshState &state);
  std::string vertexKeyOf(const tinygltf::Primitive &prim, const MeshNode &mn) const;
  void checkMeshSize() const;
  void computeNormals(uint32_t base, const std::vector<uint32_t> &idx);

  // gltf_morphs.cpp
  void readMorphTargets(const MeshNode &mn, const tinygltf::Mesh &gm,
                        const tinygltf::Primitive &prim, const std::string &ctx, uint32_t base,
                        size_t vc);

  // gltf_textures.cpp
  int baseColorImage(int material) const;
  void readDiffuseTexture();

  // gltf_animations.cpp
  void readAnimations();

  std::string path_;
  std::string stage_; // what the import is doing, for an out-of-memory error
  Reporter &reporter_;
  tinygltf::Model model_;
  Accessors accessors_{model_, path_, stage_};
  Character out_;
  std::vector<int> skins_;                         // the skins baked
  std::map<int, std::vector<size_t>> skinEntries_; // per skin, its joints' entries in skinJoints_
  std::vector<int> skinJoints_;
  std::vector<glm::dmat4> skinIbm_;
  std::vector<uint16_t> oldToNew_;
  std::vector<MeshNode> meshNodes_;
  bool hasUvs_ = false;
  EncodedImages encodedImages_;
  std::map<int, size_t> trianglesPerImage_;
};

} // namespace crowd::gltf
