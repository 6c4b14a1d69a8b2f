// Character: the editable, in-memory form of one imported glTF character (node hierarchy,
// skeleton, skinned mesh, animation clips as keyframes). Every bake reads one of these.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "crowd/formats/chunks.h"

namespace crowd {

struct Node {
  std::string name;
  int parent = -1;
  // Rest transform: TRS, or a matrix when the glTF node gives one (never animated then).
  glm::dvec3 translation{0.0};
  glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
  glm::dvec3 scale{1.0};
  bool hasMatrix = false;
  glm::dmat4 matrix{1.0};
};

enum class Interpolation { Linear, Step, CubicSpline };
enum class ChannelPath { Translation, Rotation, Scale, Weights };

struct Channel {
  int node = 0;
  ChannelPath path = ChannelPath::Translation;
  Interpolation interpolation = Interpolation::Linear;
  std::vector<double> times; // strictly increasing
  // Components per key: 3 (T, S), 4 (R, xyzw), or the node's morph target count (weights);
  // CUBICSPLINE stores in-tangent, value, out-tangent per key, as glTF does.
  size_t components = 3;
  std::vector<double> values;
};

struct AnimationClip {
  std::string name;
  double start = 0, end = 0; // seconds: the clip's key time range
  std::vector<Channel> channels;
};

// A morph target: per mesh vertex, the offset it adds at weight 1 (zero on vertices of other
// meshes). Morphing comes before skinning, as glTF orders them.
struct MorphTarget {
  std::string name;
  std::vector<glm::vec3> positions, normals; // per mesh vertex
};

// The morph targets one node's mesh brings: targets [first, first + count), driven by the node's
// "weights" channels, `defaults` when no channel drives them.
struct MorphGroup {
  int node = 0;
  uint32_t first = 0, count = 0;
};

struct SkinnedMesh {
  std::vector<glm::vec3> positions; // bind pose (model space)
  std::vector<glm::vec3> normals;
  std::vector<glm::vec2> uvs; // empty when the source has none
  std::vector<std::array<uint16_t, 4>> joints;
  std::vector<glm::vec4> weights; // sum to 1
  std::vector<uint32_t> indices;
  // Per vertex, where the importer read it (file 0; outfits renumber); empty when unknown.
  std::vector<pack::VertexSource> sources;
  std::vector<MorphTarget> morphs;
  std::vector<double> morphDefaults; // per target: its weight when no channel drives it
  struct Part {
    std::string name; // the material's
    uint32_t firstIndex = 0, indexCount = 0;
    glm::vec4 colour{1.0f};  // the material's base colour factor
    bool textured = false;   // its base colour comes from the character's diffuse texture
    bool seeThrough = false; // alpha mode MASK or BLEND: surfaces behind it may show
  };
  std::vector<Part> parts;
  size_t vertexCount() const { return positions.size(); }
};

struct DiffuseTexture {
  int width = 0, height = 0;
  std::vector<uint8_t> rgba; // rows from the top, as glTF UVs address them
};

struct Character {
  std::vector<std::string> sourceFiles; // the glTF file, then every external buffer it reads
  std::vector<Node> nodes;
  std::vector<int> nodeOrder;          // parents before children
  std::vector<int> jointNodes;         // node index of each joint
  std::vector<glm::dmat4> inverseBind; // per joint
  SkinnedMesh mesh;
  std::vector<AnimationClip> clips;
  std::vector<MorphGroup> morphGroups;   // which node's weights drive which mesh.morphs
  std::optional<DiffuseTexture> diffuse; // the base-colour texture the mesh uses, if any
  bool skinned = true; // false: the file has no skin (its meshes ride their nodes rigidly)

  size_t jointCount() const { return jointNodes.size(); }
  std::vector<std::string> clipNames() const {
    std::vector<std::string> names;
    for (const auto &clip : clips)
      names.push_back(clip.name);
    return names;
  }
  std::string jointName(size_t j) const { return nodes[size_t(jointNodes[j])].name; }
  // The targets `node`'s weights drive, or null.
  const MorphGroup *morphGroupOf(int node) const {
    for (const auto &g : morphGroups)
      if (g.node == node)
        return &g;
    return nullptr;
  }
};

} // namespace crowd
