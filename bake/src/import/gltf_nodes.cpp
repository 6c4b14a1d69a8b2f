#include "importer.h"

#include <algorithm>
#include <array>

#include <glm/gtc/type_ptr.hpp>

#include "crowd/formats/limits.h"

namespace crowd::gltf {

void Importer::buildHierarchy() {
  const size_t n = model_.nodes.size();
  out_.nodes.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const auto &src = model_.nodes[i];
    Node &node = out_.nodes[i];
    node.name = src.name.empty() ? "node" + std::to_string(i) : src.name;
    std::string ctx = "node " + std::to_string(i) + " '" + node.name + "'";
    auto finite = [&](const std::vector<double> &v, const char *field) {
      for (double d : v)
        if (!std::isfinite(d))
          fail(ctx + ": " + field + " is not finite");
    };
    finite(src.translation, "translation");
    finite(src.rotation, "rotation");
    finite(src.scale, "scale");
    finite(src.matrix, "matrix");
    if (src.matrix.size() == 16) {
      node.hasMatrix = true;
      node.matrix = glm::make_mat4(src.matrix.data());
    }
    if (src.translation.size() == 3)
      node.translation = glm::make_vec3(src.translation.data());
    if (src.rotation.size() == 4)
      node.rotation = glm::normalize(
          glm::dquat(src.rotation[3], src.rotation[0], src.rotation[1], src.rotation[2]));
    if (src.scale.size() == 3)
      node.scale = glm::make_vec3(src.scale.data());
    for (int child : src.children) {
      if (child < 0 || size_t(child) >= n)
        fail(ctx + ": child " + std::to_string(child) + " does not exist");
      if (size_t(child) == i)
        fail("node graph has a cycle: " + ctx + " is its own child");
      if (out_.nodes[size_t(child)].parent >= 0)
        fail("node " + std::to_string(child) +
             " has two parents (the node graph must be a forest)");
      out_.nodes[size_t(child)].parent = int(i);
    }
  }
  // Depth-first from the roots; a node never reached sits on a cycle.
  std::vector<std::vector<int>> children(n);
  for (size_t i = 0; i < n; ++i)
    if (out_.nodes[i].parent >= 0)
      children[size_t(out_.nodes[i].parent)].push_back(int(i));
  std::vector<int> stack;
  for (size_t i = n; i-- > 0;)
    if (out_.nodes[i].parent < 0)
      stack.push_back(int(i));
  while (!stack.empty()) {
    int v = stack.back();
    stack.pop_back();
    out_.nodeOrder.push_back(v);
    for (auto it = children[size_t(v)].rbegin(); it != children[size_t(v)].rend(); ++it)
      stack.push_back(*it);
  }
  if (out_.nodeOrder.size() != n)
    fail("node graph has a cycle");
  makeNamesUnique(out_.nodes, "duplicate_node_names", "nodes", "outfits match joints by name");
}

// Whether the node's rest transform, with its ancestors', mirrors (a negative determinant).
bool Importer::mirrors(int node) const {
  bool odd = false;
  for (int n = node; n >= 0; n = out_.nodes[size_t(n)].parent) {
    const Node &nd = out_.nodes[size_t(n)];
    const glm::dvec3 &s = nd.scale;
    odd ^= (nd.hasMatrix ? glm::determinant(nd.matrix) : s.x * s.y * s.z) < 0;
  }
  return odd;
}

bool Importer::hasAncestorIn(int node, const std::set<int> &set) const {
  for (int p = out_.nodes[size_t(node)].parent; p >= 0; p = out_.nodes[size_t(p)].parent)
    if (set.count(p))
      return true;
  return false;
}

// The skins, their joints merged into one skeleton, the mesh nodes baked (skinned or rigid), and
// the joints in parent-before-child order.
void Importer::selectMeshes(const ImportOptions &options) {
  const auto &nodes = model_.nodes;
  auto checkRef = [&](size_t i) {
    const auto &nd = nodes[i];
    if (nd.mesh >= 0 && size_t(nd.mesh) >= model_.meshes.size())
      fail("node " + std::to_string(i) + ": mesh " + std::to_string(nd.mesh) + " does not exist");
    if (nd.skin >= 0 && size_t(nd.skin) >= model_.skins.size())
      fail("node " + std::to_string(i) + ": skin " + std::to_string(nd.skin) + " does not exist");
  };
  for (size_t i = 0; i < nodes.size(); ++i)
    checkRef(i);
  chooseSkins(options);
  const std::set<int> jointSet = mergeSkinJoints();
  chooseMeshNodes(options, jointSet);
  orderJoints();
}

// The skins baked: every skin a mesh node uses (the named mesh's, with --mesh), merged into
// one skeleton; a file whose skins bind no mesh gives its largest, for rigid parts under it.
void Importer::chooseSkins(const ImportOptions &options) {
  const auto &nodes = model_.nodes;
  skins_.clear();
  if (!options.mesh.empty()) {
    bool found = false;
    for (size_t i = 0; i < nodes.size(); ++i) {
      const auto &nd = nodes[i];
      if (nd.mesh >= 0 && model_.meshes[size_t(nd.mesh)].name == options.mesh) {
        if (!found && nd.skin >= 0)
          skins_.push_back(nd.skin);
        found = true;
      }
    }
    if (!found) {
      std::string names;
      for (const auto &m : model_.meshes)
        names += (names.empty() ? "" : ", ") + m.name;
      fail("no mesh named '" + options.mesh + "' used by a node (meshes: " + names + ")");
    }
  } else {
    std::set<int> used;
    for (const auto &nd : nodes)
      if (nd.mesh >= 0 && nd.skin >= 0)
        used.insert(nd.skin);
    skins_.assign(used.begin(), used.end());
    int largest = -1;
    for (size_t s = 0; s < model_.skins.size(); ++s)
      if (largest < 0 ||
          model_.skins[s].joints.size() > model_.skins[size_t(largest)].joints.size())
        largest = int(s);
    if (skins_.empty() && largest >= 0)
      skins_.push_back(largest);
  }
}

// Their joints, one entry per (node, inverse bind matrix): a node two skins bind alike is one
// joint, bound differently it is two.
std::set<int> Importer::mergeSkinJoints() {
  const auto &nodes = model_.nodes;
  std::set<int> jointSet;
  std::map<std::pair<int, std::array<double, 16>>, size_t> entryOf;
  skinEntries_.clear();
  for (int s : skins_) {
    const auto &skin = model_.skins[size_t(s)];
    std::string ctx = "skin " + std::to_string(s);
    if (skin.joints.empty())
      fail(ctx + " has no joints");
    if (skin.joints.size() > limits::kJoints) // before its matrices are read
      fail(ctx + ": " + std::to_string(skin.joints.size()) + " joints, over the limit of " +
           std::to_string(limits::kJoints));
    std::set<int> listed;
    for (int j : skin.joints) {
      if (j < 0 || size_t(j) >= nodes.size())
        fail(ctx + ": joint node " + std::to_string(j) + " does not exist");
      if (!listed.insert(j).second)
        fail(ctx + ": node " + std::to_string(j) + " is listed twice as a joint");
      jointSet.insert(j);
    }
    std::shared_ptr<const std::vector<double>> ibm;
    if (skin.inverseBindMatrices >= 0) {
      if (accessors_.type(skin.inverseBindMatrices, ctx) != TINYGLTF_TYPE_MAT4 ||
          accessors_.count(skin.inverseBindMatrices) < skin.joints.size())
        fail(ctx + ": inverseBindMatrices must be MAT4 with one per joint");
      ibm = accessors_.read(skin.inverseBindMatrices, ctx + " inverseBindMatrices");
    }
    auto &entries = skinEntries_[s];
    for (size_t j = 0; j < skin.joints.size(); ++j) {
      std::array<double, 16> m;
      for (size_t k = 0; k < 16; ++k)
        m[k] = ibm ? (*ibm)[j * 16 + k] : (k % 5 == 0 ? 1.0 : 0.0);
      auto [it, fresh] = entryOf.try_emplace({skin.joints[j], m}, skinJoints_.size());
      if (fresh) {
        skinJoints_.push_back(skin.joints[j]);
        skinIbm_.push_back(glm::make_mat4(m.data()));
      }
      entries.push_back(it->second);
    }
    if (skinJoints_.size() > limits::kJoints)
      fail("the skins bind " + std::to_string(skinJoints_.size()) + " joints, over the limit of " +
           std::to_string(limits::kJoints));
  }
  return jointSet;
}

// The nodes whose meshes are baked: skinned by a chosen skin, or rigid (no skin) under a joint or
// in a file with no skin, each such node then a joint of its own.
void Importer::chooseMeshNodes(const ImportOptions &options, const std::set<int> &jointSet) {
  const auto &nodes = model_.nodes;
  for (size_t i = 0; i < nodes.size(); ++i) {
    const auto &nd = nodes[i];
    if (nd.mesh < 0)
      continue;
    bool named = options.mesh.empty() || model_.meshes[size_t(nd.mesh)].name == options.mesh;
    if (!named)
      continue;
    if (nd.skin >= 0 && skinEntries_.count(nd.skin)) {
      meshNodes_.push_back({int(i), -1, 0, nd.skin});
    } else if (nd.skin < 0 && (skins_.empty() || hasAncestorIn(int(i), jointSet))) {
      meshNodes_.push_back({int(i), int(i)}); // rigid: the node itself becomes a joint
    }
  }
  if (meshNodes_.empty())
    fail("no mesh to bake (no node uses a mesh with the chosen skin)");
}

void Importer::orderJoints() {
  const auto &nodes = model_.nodes;
  out_.skinned = !skins_.empty();
  // Joints in parent-before-child order so the pack's skeleton can require parent < index.
  std::vector<int> jointNodes = skinJoints_;
  std::vector<glm::dmat4> ibms = skinIbm_;
  std::vector<size_t> rigidOld(meshNodes_.size());
  for (size_t m = 0; m < meshNodes_.size(); ++m)
    if (meshNodes_[m].rigid >= 0) {
      rigidOld[m] = jointNodes.size();
      jointNodes.push_back(meshNodes_[m].rigid);
      ibms.push_back(glm::dmat4(1.0));
    }
  if (jointNodes.size() > 65535)
    fail("more than 65535 joints");
  std::vector<size_t> rank(nodes.size());
  for (size_t k = 0; k < out_.nodeOrder.size(); ++k)
    rank[size_t(out_.nodeOrder[k])] = k;
  std::vector<size_t> perm(jointNodes.size());
  for (size_t k = 0; k < perm.size(); ++k)
    perm[k] = k;
  std::sort(perm.begin(), perm.end(), [&](size_t a, size_t b) {
    return rank[size_t(jointNodes[a])] < rank[size_t(jointNodes[b])];
  });
  oldToNew_.assign(perm.size(), 0);
  for (size_t k = 0; k < perm.size(); ++k) {
    oldToNew_[perm[k]] = uint16_t(k);
    out_.jointNodes.push_back(jointNodes[perm[k]]);
    out_.inverseBind.push_back(ibms[perm[k]]);
  }
  for (size_t m = 0; m < meshNodes_.size(); ++m)
    if (meshNodes_[m].rigid >= 0)
      meshNodes_[m].rigidJoint = oldToNew_[rigidOld[m]];
}

} // namespace crowd::gltf
