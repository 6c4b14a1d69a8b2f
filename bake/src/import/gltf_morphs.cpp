#include "importer.h"

#include "crowd/formats/limits.h"

namespace crowd::gltf {

// The morph targets of a primitive whose vertices were just appended at `base`: the node's
// group of targets is made with its first primitive (names from the mesh's extras, default
// weights from the node or the mesh); every target's offsets are stored per mesh vertex.
void Importer::readMorphTargets(const MeshNode &mn, const tinygltf::Mesh &gm,
                                const tinygltf::Primitive &prim, const std::string &ctx,
                                uint32_t base, size_t vc) {
  auto &mesh = out_.mesh;
  const MorphGroup *group = out_.morphGroupOf(mn.node);
  if (!group && !prim.targets.empty()) {
    const size_t count = prim.targets.size();
    if (mesh.morphs.size() + count > limits::kMorphTargets)
      fail(ctx + ": more than " + std::to_string(limits::kMorphTargets) + " morph targets");
    const auto &node = model_.nodes[size_t(mn.node)];
    const auto &defaults = node.weights.empty() ? gm.weights : node.weights;
    if (!defaults.empty() && defaults.size() != count)
      fail(ctx + ": " + std::to_string(defaults.size()) + " default weights for " +
           std::to_string(count) + " morph targets");
    const tinygltf::Value names =
        gm.extras.IsObject() ? gm.extras.Get("targetNames") : tinygltf::Value();
    for (size_t t = 0; t < count; ++t) {
      MorphTarget target;
      if (names.IsArray() && t < names.ArrayLen() && names.Get(int(t)).IsString())
        target.name = names.Get(int(t)).Get<std::string>();
      if (target.name.empty())
        target.name = gm.name + "." + std::to_string(t);
      mesh.morphs.push_back(std::move(target));
      mesh.morphDefaults.push_back(defaults.empty() ? 0.0 : defaults[t]);
    }
    out_.morphGroups.push_back({mn.node, uint32_t(mesh.morphs.size() - count), uint32_t(count)});
    group = &out_.morphGroups.back();
  }
  if (uint64_t(mesh.morphs.size()) * mesh.vertexCount() > limits::kMorphOffsets)
    fail(ctx + ": " + std::to_string(mesh.morphs.size()) + " morph targets x " +
         std::to_string(mesh.vertexCount()) + " vertices is over the limit of " +
         std::to_string(limits::kMorphOffsets));
  for (auto &target : mesh.morphs) {
    target.positions.resize(mesh.vertexCount(), glm::vec3(0));
    target.normals.resize(mesh.vertexCount(), glm::vec3(0));
  }
  const size_t expected = group ? group->count : 0;
  if (prim.targets.size() != expected)
    fail(ctx + ": " + std::to_string(prim.targets.size()) + " morph targets, but the mesh's " +
         "first primitive has " + std::to_string(expected) + " (glTF requires the same count)");
  for (size_t t = 0; t < prim.targets.size(); ++t) {
    auto &target = mesh.morphs[group->first + t];
    for (const auto &[attribute, accessor] : prim.targets[t]) {
      const bool position = attribute == "POSITION";
      if (!position && attribute != "NORMAL")
        continue; // tangents and the like do not reach the player
      const std::string actx = ctx + ", morph target " + std::to_string(t) + " " + attribute;
      if (accessors_.type(accessor, actx) != TINYGLTF_TYPE_VEC3 || accessors_.count(accessor) != vc)
        fail(actx + ": type or count differs from POSITION");
      const auto data = accessors_.read(accessor, actx);
      auto &offsets = position ? target.positions : target.normals;
      for (size_t v = 0; v < vc; ++v)
        offsets[base + v] = glm::vec3((*data)[v * 3], (*data)[v * 3 + 1], (*data)[v * 3 + 2]);
    }
  }
}

} // namespace crowd::gltf
