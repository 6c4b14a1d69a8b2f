#include "crowd/bake/import.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>

#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "base_colour_uv.h"
#include "crowd/bake/input_files.h"
#include "crowd/formats/error.h"
#include "crowd/runtime/images.h"
#include "crowd/runtime/json_checker.h"
#include "gltf_schema.h"
#include "meshopt_views.h"
#include "nearest_influences.h"
#include "triangle_list.h"
#include "unique_names.h"

namespace crowd {
namespace {

using tinygltf::Model;

std::string oneLine(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
    s.pop_back();
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

// Images are kept encoded as tinygltf hands them over; only the diffuse texture the mesh uses is
// decoded (through OpenImageIO), and an image that cannot be decoded is a warning, not a failure.
using EncodedImages = std::map<int, std::vector<uint8_t>>;
struct ImageSink {
  EncodedImages *images;
  const Model *model; // as tinygltf has parsed it so far: its buffers and views come first
};
bool keepEncodedImage(tinygltf::Image *image, const int index, std::string *err, std::string *, int,
                      int, const unsigned char *bytes, int size, void *user) {
  const ImageSink &sink = *static_cast<ImageSink *>(user);
  if (image->bufferView >= 0) { // tinygltf does not check the view against its buffer
    const auto &view = sink.model->bufferViews[size_t(image->bufferView)];
    const auto &buffer = sink.model->buffers[size_t(view.buffer)];
    if (view.byteOffset > buffer.data.size() ||
        view.byteLength > buffer.data.size() - view.byteOffset) {
      *err += "image " + std::to_string(index) + ": its bufferView " +
              std::to_string(image->bufferView) + " runs past the end of buffer " +
              std::to_string(view.buffer) + " (" + std::to_string(buffer.data.size()) + " bytes)";
      return false;
    }
  }
  if (bytes && size > 0)
    (*sink.images)[index].assign(bytes, bytes + size);
  return true;
}

constexpr int kMaxTextureSide = limits::kImageSide;

class Importer {
public:
  Importer(std::string path, Reporter &reporter) : path_(std::move(path)), reporter_(reporter) {}

  Character run(const ImportOptions &options) {
    try {
      load(options.input);
      buildHierarchy();
      selectMeshes(options);
      readMeshes();
      readAnimations();
      readDiffuseTexture();
    } catch (const std::bad_alloc &) {
      fail("out of memory while " + stage_);
    }
    return std::move(out_);
  }

private:
  struct MeshNode {
    int node;
    int rigid; // node that acts as the joint of a rigid mesh, or -1 when skinned
    uint16_t rigidJoint = 0;
    int skin = -1; // a skinned mesh's skin
  };

  [[noreturn]] void fail(const std::string &what) const { throw Error(path_ + ": " + what); }

  // tinygltf reads external buffers and images through these callbacks, so every URI goes
  // through resolveNamedInput and readInputFile; the first refusal becomes the import's error.
  struct Confinement {
    const std::string *gltf;
    const InputPolicy *policy;
    std::string problem;
    std::vector<std::string> read; // every external file read, in order
  };
  static constexpr const char *kRefused = "\x01refused";
  static std::string expandUri(const std::string &uri, void *user) {
    auto *c = static_cast<Confinement *>(user);
    // tinygltf also tries "./URI": the same name, relative to the glTF's folder.
    const std::string name = uri.rfind("./", 0) == 0 ? uri.substr(2) : uri;
    try {
      return resolveNamedInput(name, *c->gltf, *c->policy, "URI");
    } catch (const Error &e) {
      if (c->problem.empty())
        c->problem = e.what();
      return kRefused;
    }
  }
  static bool uriExists(const std::string &path, void *) {
    std::error_code ec;
    return path != kRefused && std::filesystem::exists(path, ec);
  }
  static bool readUri(std::vector<unsigned char> *out, std::string *err, const std::string &path,
                      void *user) {
    auto *c = static_cast<Confinement *>(user);
    try {
      *out = readInputFile(path, *c->policy);
      if (std::find(c->read.begin(), c->read.end(), path) == c->read.end())
        c->read.push_back(path);
      return true;
    } catch (const Error &e) {
      if (c->problem.empty())
        c->problem = *c->gltf + ": URI " + e.what();
      *err += e.what();
      return false;
    }
  }
  static bool noWrite(std::string *, const std::string &, const std::vector<unsigned char> &,
                      void *) {
    return false;
  }

  void load(const InputPolicy &policy) {
    stage_ = "reading the file";
    std::vector<uint8_t> bytes = readInputFile(path_, policy);
    bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    // The JSON's nesting is checked before tinygltf parses it: its parser recurses.
    std::string_view json(reinterpret_cast<const char *>(bytes.data()), bytes.size());
    if (binary) {
      uint32_t length = 0;
      if (bytes.size() >= 20)
        std::memcpy(&length, bytes.data() + 12, 4);
      json = json.substr(std::min<size_t>(20, json.size()), length);
    }
    runtime::checkJsonDepth(json, path_);
    if (binary && bytes.size() >= 8 && bytes[4] != 2)
      fail("GLB container version " + std::to_string(bytes[4]) + " is not 2");
    stage_ = "decoding compressed buffer views";
    const auto readBuffer = [&](const std::string &uri) {
      return readInputFile(resolveNamedInput(uriAsRead(uri), path_, policy, "URI"), policy);
    };
    if (decodeMeshoptViews(bytes, path_, readBuffer)) { // now a GLB, the views decoded
      binary = true;
      uint32_t length = 0;
      std::memcpy(&length, bytes.data() + 12, 4);
      json = std::string_view(reinterpret_cast<const char *>(bytes.data()) + 20, length);
    }
    checkGltfJson(json, path_);
    stage_ = "parsing the glTF JSON";
    Confinement confinement{&path_, &policy, {}, {}};
    tinygltf::TinyGLTF loader;
    ImageSink images{&encodedImages_, &model_};
    loader.SetImageLoader(keepEncodedImage, &images);
    loader.SetFsCallbacks({uriExists, expandUri, readUri, noWrite, &confinement});
    std::string err, warn;
    // base_dir stays empty: URIs reach expandUri as written (percent-decoded), and are resolved
    // against the glTF's own folder there, never the working directory.
    bool ok = binary ? loader.LoadBinaryFromMemory(&model_, &err, &warn, bytes.data(),
                                                   unsigned(bytes.size()), "")
                     : loader.LoadASCIIFromString(&model_, &err, &warn,
                                                  reinterpret_cast<const char *>(bytes.data()),
                                                  unsigned(bytes.size()), "");
    if (!confinement.problem.empty())
      throw Error(confinement.problem);
    if (!ok)
      fail("not a readable glTF: " + oneLine(err.empty() ? warn : err));
    out_.sourceFiles.push_back(path_);
    for (const auto &file : confinement.read)
      out_.sourceFiles.push_back(file);
  }

  // --- accessors -------------------------------------------------------------------------

  static int components(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    case TINYGLTF_TYPE_MAT2:
      return 4;
    case TINYGLTF_TYPE_MAT3:
      return 9;
    case TINYGLTF_TYPE_MAT4:
      return 16;
    default:
      return 0;
    }
  }

  static double readComponent(const uint8_t *p, int componentType, bool normalized) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized ? *p / 255.0 : *p;
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    }
  }

  static int componentSize(int componentType) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
    }
  }

  // Bytes of `count` elements of `elemSize` at `offset` with `stride` inside buffer view `view`.
  const uint8_t *viewRange(int view, size_t offset, size_t count, size_t stride, size_t elemSize,
                           const std::string &what) const {
    if (view < 0 || size_t(view) >= model_.bufferViews.size())
      fail(what + ": bufferView " + std::to_string(view) + " does not exist");
    const auto &bv = model_.bufferViews[size_t(view)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size())
      fail(what + ": buffer " + std::to_string(bv.buffer) + " does not exist");
    const auto &buf = model_.buffers[size_t(bv.buffer)].data;
    if (bv.byteOffset > buf.size() || bv.byteLength > buf.size() - bv.byteOffset)
      fail(what + ": bufferView " + std::to_string(view) + " lies outside buffer " +
           std::to_string(bv.buffer) + " (" + std::to_string(buf.size()) + " bytes)");
    if (count > 0) {
      // Division avoids overflow on absurd counts.
      if (offset > bv.byteLength || elemSize > bv.byteLength - offset ||
          (count - 1) > (bv.byteLength - offset - elemSize) / stride)
        fail(what + ": " + std::to_string(count) + " elements run past the end of bufferView " +
             std::to_string(view));
    }
    return buf.data() + bv.byteOffset + offset;
  }

  // Every element of accessor `index` as doubles (count * components), normalised per spec.
  // The count is checked against the limits and the buffer view before anything is allocated;
  // an accessor shared by several primitives is read once.
  std::shared_ptr<const std::vector<double>> readAccessor(int index, const std::string &what,
                                                          bool finite = true) {
    auto cached = accessorCache_.find({index, finite});
    if (cached != accessorCache_.end())
      return cached->second;
    std::string ctx = what + ", accessor " + std::to_string(index);
    stage_ = "reading " + ctx;
    if (index < 0 || size_t(index) >= model_.accessors.size())
      fail(ctx + ": does not exist");
    const auto &acc = model_.accessors[size_t(index)];
    int nc = components(acc.type);
    int cs = componentSize(acc.componentType);
    if (nc == 0 || cs == 0)
      fail(ctx + ": unsupported type or component type");
    if (acc.count > limits::kAccessorElements)
      fail(ctx + ": count " + std::to_string(acc.count) + " is over the limit of " +
           std::to_string(limits::kAccessorElements) + " elements");
    size_t elemSize = size_t(nc) * size_t(cs);
    const uint8_t *p = nullptr;
    size_t stride = elemSize;
    if (acc.bufferView >= 0) {
      if (size_t(acc.bufferView) < model_.bufferViews.size() &&
          model_.bufferViews[size_t(acc.bufferView)].byteStride) {
        stride = model_.bufferViews[size_t(acc.bufferView)].byteStride;
        if (stride < elemSize)
          fail(ctx + ": bufferView byteStride " + std::to_string(stride) +
               " is smaller than an element (" + std::to_string(elemSize) + " bytes)");
      }
      p = viewRange(acc.bufferView, acc.byteOffset, acc.count, stride, elemSize, ctx);
    }
    auto shared = std::make_shared<std::vector<double>>(acc.count * size_t(nc), 0.0);
    auto &out = *shared;
    if (p)
      for (size_t i = 0; i < acc.count; ++i)
        for (int c = 0; c < nc; ++c)
          out[i * size_t(nc) + size_t(c)] =
              readComponent(p + i * stride + size_t(c * cs), acc.componentType, acc.normalized);
    if (acc.sparse.isSparse) {
      size_t n = size_t(std::max(acc.sparse.count, 0));
      int ics = componentSize(acc.sparse.indices.componentType);
      if (ics == 0 || n > acc.count)
        fail(ctx + ": bad sparse block");
      const uint8_t *ip = viewRange(acc.sparse.indices.bufferView,
                                    size_t(std::max(acc.sparse.indices.byteOffset, 0)), n,
                                    size_t(ics), size_t(ics), ctx + " sparse indices");
      const uint8_t *vp =
          viewRange(acc.sparse.values.bufferView, size_t(std::max(acc.sparse.values.byteOffset, 0)),
                    n, elemSize, elemSize, ctx + " sparse values");
      for (size_t k = 0; k < n; ++k) {
        auto target =
            size_t(readComponent(ip + k * size_t(ics), acc.sparse.indices.componentType, false));
        if (target >= acc.count)
          fail(ctx + ": sparse index out of range");
        for (int c = 0; c < nc; ++c)
          out[target * size_t(nc) + size_t(c)] =
              readComponent(vp + k * elemSize + size_t(c * cs), acc.componentType, acc.normalized);
      }
    }
    if (finite)
      for (size_t i = 0; i < out.size(); ++i)
        if (!std::isfinite(out[i]))
          fail(ctx + ": element " + std::to_string(i / size_t(nc)) + " is NaN or infinite");
    accessorCache_[{index, finite}] = shared;
    return shared;
  }

  // An accessor's declared count (not yet checked against its buffer view).
  size_t accessorCount(int index) const {
    if (index < 0 || size_t(index) >= model_.accessors.size())
      fail("accessor " + std::to_string(index) + ": does not exist");
    return model_.accessors[size_t(index)].count;
  }
  int accessorType(int index, const std::string &what) const {
    if (index < 0 || size_t(index) >= model_.accessors.size())
      fail(what + ", accessor " + std::to_string(index) + ": does not exist");
    return model_.accessors[size_t(index)].type;
  }

  // --- nodes -----------------------------------------------------------------------------

  void buildHierarchy() {
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

  // Renames what repeats an earlier name in `items` (unique_names.h), saying so under `code`.
  template <class T>
  void makeNamesUnique(std::vector<T> &items, const std::string &code, const std::string &what,
                       const std::string &why) {
    std::vector<std::string *> names;
    for (T &item : items)
      names.push_back(&item.name);
    warnCount(code, gltf::makeUnique(names),
              what + " repeat an earlier one's name: renamed NAME_2, NAME_3, ... (" + why + ")");
  }

  // A warning under `code` that starts with how many (`count` things `what`), where any were.
  void warnCount(const std::string &code, size_t count, const std::string &what) {
    if (count)
      reporter_.warn(code, std::to_string(count) + " " + what, count);
  }

  // Whether the node's rest transform, with its ancestors', mirrors (a negative determinant).
  bool mirrors(int node) const {
    bool odd = false;
    for (int n = node; n >= 0; n = out_.nodes[size_t(n)].parent) {
      const Node &nd = out_.nodes[size_t(n)];
      const glm::dvec3 &s = nd.scale;
      odd ^= (nd.hasMatrix ? glm::determinant(nd.matrix) : s.x * s.y * s.z) < 0;
    }
    return odd;
  }

  bool hasAncestorIn(int node, const std::set<int> &set) const {
    for (int p = out_.nodes[size_t(node)].parent; p >= 0; p = out_.nodes[size_t(p)].parent)
      if (set.count(p))
        return true;
    return false;
  }

  void selectMeshes(const ImportOptions &options) {
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

    // The skins baked: every skin a mesh node uses (the named mesh's, with --mesh), merged into
    // one skeleton; a file whose skins bind no mesh gives its largest, for rigid parts under it.
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

    // Their joints, one entry per (node, inverse bind matrix): a node two skins bind alike is one
    // joint, bound differently it is two.
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
        if (accessorType(skin.inverseBindMatrices, ctx) != TINYGLTF_TYPE_MAT4 ||
            accessorCount(skin.inverseBindMatrices) < skin.joints.size())
          fail(ctx + ": inverseBindMatrices must be MAT4 with one per joint");
        ibm = readAccessor(skin.inverseBindMatrices, ctx + " inverseBindMatrices");
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
        fail("the skins bind " + std::to_string(skinJoints_.size()) +
             " joints, over the limit of " + std::to_string(limits::kJoints));
    }

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

  // --- meshes ----------------------------------------------------------------------------

  void readMeshes() {
    std::vector<std::string> partOrder;
    std::vector<std::vector<uint32_t>> partTriangles;
    std::vector<SkinnedMesh::Part> partLooks; // material look of each part
    auto &mesh = out_.mesh;
    size_t moreThan4 = 0, renormalised = 0, missingNormals = 0, duplicatePrimitives = 0,
           pointsOrLines = 0, unweighted = 0, mirroredPrimitives = 0;
    std::map<std::string, uint32_t> vertexBases; // first vertex of each distinct vertex set
    std::set<std::string> seenPrimitives;
    checkMeshSize();
    for (const auto &mn : meshNodes_) {
      const auto &gm = model_.meshes[size_t(model_.nodes[size_t(mn.node)].mesh)];
      const bool mirrored = mirrors(mn.node); // its triangles are wound clockwise (below)
      for (size_t pi = 0; pi < gm.primitives.size(); ++pi) {
        const auto &prim = gm.primitives[pi];
        std::string ctx = "mesh '" + gm.name + "', primitive " + std::to_string(pi);
        if (prim.mode < -1 || prim.mode > gltf::kTriangleFan)
          fail(ctx + ": mode " + std::to_string(prim.mode) + " is not a glTF primitive mode");
        if (!gltf::drawsTriangles(prim.mode)) {
          ++pointsOrLines;
          continue;
        }
        auto attr = [&](const std::string &name) {
          auto it = prim.attributes.find(name);
          return it == prim.attributes.end() ? -1 : it->second;
        };
        int posAcc = attr("POSITION");
        if (posAcc < 0)
          fail(ctx + ": no POSITION attribute");
        if (accessorType(posAcc, ctx + " POSITION") != TINYGLTF_TYPE_VEC3)
          fail(ctx + " POSITION: must be VEC3");
        const size_t vc = accessorCount(posAcc);
        // Primitives repeating another's vertices share them; one repeating another's vertices,
        // indices and material too is dropped (some exporters write hundreds).
        const std::string vertexKey = vertexKeyOf(prim, mn);
        if (!seenPrimitives
                 .insert(vertexKey + "|" + std::to_string(prim.indices) + "|" +
                         std::to_string(prim.material))
                 .second) {
          ++duplicatePrimitives;
          continue;
        }
        const auto [known, fresh] =
            vertexBases.try_emplace(vertexKey, uint32_t(mesh.positions.size()));
        const auto posData = readAccessor(posAcc, ctx + " POSITION");
        const std::vector<double> &pos = *posData;
        auto sameCount = [&](int acc, const char *name, int type) {
          if (accessorType(acc, ctx + " " + name) != type || accessorCount(acc) != vc)
            fail(ctx + " " + name + ": type or count differs from POSITION");
        };
        std::vector<double> nrm, uv;
        if (int a = attr("NORMAL"); a >= 0) {
          sameCount(a, "NORMAL", TINYGLTF_TYPE_VEC3);
          nrm = *readAccessor(a, ctx + " NORMAL");
        } else {
          missingNormals += fresh;
        }
        // The set the base-colour texture reads, through its KHR_texture_transform.
        const gltf::BaseColourUv uvMap = gltf::baseColourUv(model_, prim.material);
        const std::string uvName = "TEXCOORD_" + std::to_string(uvMap.set);
        if (int a = attr(uvName); a >= 0) {
          sameCount(a, uvName.c_str(), TINYGLTF_TYPE_VEC2);
          uv = *readAccessor(a, ctx + " " + uvName);
          for (size_t k = 0; !uvMap.identity && k + 1 < uv.size(); k += 2) {
            const glm::dvec3 t = uvMap.transform * glm::dvec3(uv[k], uv[k + 1], 1);
            if (!std::isfinite(t.x) || !std::isfinite(t.y))
              fail(ctx + " " + uvName + ": KHR_texture_transform takes vertex " +
                   std::to_string(k / 2) + "'s UV past the range of a number");
            uv[k] = t.x, uv[k + 1] = t.y;
          }
        }
        std::vector<uint32_t> idx;
        if (prim.indices >= 0) {
          const auto rawData = readAccessor(prim.indices, ctx + " indices");
          const std::vector<double> &raw = *rawData;
          for (size_t k = 0; k < raw.size(); ++k) {
            if (raw[k] < 0 || raw[k] >= double(vc))
              fail(ctx + " indices: index " + std::to_string(k) + " = " +
                   std::to_string(uint64_t(raw[k])) + " >= vertex count " + std::to_string(vc));
            idx.push_back(uint32_t(raw[k]));
          }
        } else {
          for (size_t k = 0; k < vc; ++k)
            idx.push_back(uint32_t(k));
        }
        idx = gltf::asTriangleList(prim.mode, std::move(idx));
        if (idx.size() % 3 != 0)
          fail(ctx + ": index count " + std::to_string(idx.size()) + " is not a multiple of 3");

        // Influences: every JOINTS_n/WEIGHTS_n pair, largest 4 kept.
        std::vector<std::vector<std::pair<double, int>>> infl(vc);
        if (fresh && mn.rigid < 0) {
          const std::vector<size_t> &entries = skinEntries_.at(mn.skin);
          const size_t jointCount = entries.size();
          for (int set = 0;; ++set) {
            int ja = attr("JOINTS_" + std::to_string(set)),
                wa = attr("WEIGHTS_" + std::to_string(set));
            if (ja < 0 && wa < 0)
              break;
            if (ja < 0 || wa < 0)
              fail(ctx + ": JOINTS_" + std::to_string(set) + " without WEIGHTS_" +
                   std::to_string(set));
            sameCount(ja, "JOINTS", TINYGLTF_TYPE_VEC4);
            sameCount(wa, "WEIGHTS", TINYGLTF_TYPE_VEC4);
            const auto jData = readAccessor(ja, ctx + " JOINTS_" + std::to_string(set));
            const auto wData = readAccessor(wa, ctx + " WEIGHTS_" + std::to_string(set));
            const std::vector<double> &jv = *jData, &wv = *wData;
            for (size_t v = 0; v < vc; ++v)
              for (int k = 0; k < 4; ++k) {
                double w = wv[v * 4 + size_t(k)], j = jv[v * 4 + size_t(k)];
                if (w < 0)
                  fail(ctx + " WEIGHTS_" + std::to_string(set) + ": vertex " + std::to_string(v) +
                       " has negative weight " + std::to_string(w));
                if (w == 0)
                  continue;
                if (j < 0 || j >= double(jointCount))
                  fail(ctx + " JOINTS_" + std::to_string(set) + ": vertex " + std::to_string(v) +
                       " uses joint " + std::to_string(int64_t(j)) + " but the skin has " +
                       std::to_string(jointCount));
                infl[v].push_back({w, int(entries[size_t(j)])});
              }
          }
          if (attr("JOINTS_0") < 0)
            fail(ctx + ": skinned node without JOINTS_0/WEIGHTS_0");
          unweighted += gltf::borrowNearestInfluences(infl, pos);
        }

        const uint32_t base = known->second;
        const int meshIndex = model_.nodes[size_t(mn.node)].mesh;
        for (size_t v = 0; fresh && v < vc; ++v) {
          mesh.sources.push_back({0, mn.node, meshIndex, int32_t(pi), int32_t(v)});
          mesh.positions.push_back(glm::vec3(pos[v * 3], pos[v * 3 + 1], pos[v * 3 + 2]));
          mesh.normals.push_back(
              nrm.empty() ? glm::vec3(0) : glm::vec3(nrm[v * 3], nrm[v * 3 + 1], nrm[v * 3 + 2]));
          mesh.uvs.push_back(uv.empty() ? glm::vec2(0) : glm::vec2(uv[v * 2], uv[v * 2 + 1]));
          std::array<uint16_t, 4> ids{0, 0, 0, 0};
          glm::vec4 ws(0);
          if (mn.rigid >= 0) {
            ids[0] = mn.rigidJoint;
            ws[0] = 1;
          } else {
            auto &list = infl[v];
            if (list.empty())
              fail(ctx + ": no vertex has a joint weight (vertex " + std::to_string(v) +
                   " has all-zero weights)");
            std::sort(list.begin(), list.end(), [](auto &a, auto &b) {
              return a.first != b.first ? a.first > b.first : a.second < b.second;
            });
            double total = 0; // of every influence: dropping past the 4th is counted apart
            for (auto &[w, j] : list)
              total += w;
            if (std::abs(total - 1.0) > 2e-3)
              ++renormalised;
            if (list.size() > 4) {
              ++moreThan4;
              list.resize(4);
            }
            double sum = 0;
            for (auto &[w, j] : list)
              sum += w;
            for (size_t k = 0; k < list.size(); ++k) {
              ids[k] = oldToNew_[size_t(list[k].second)];
              ws[int(k)] = float(list[k].first / sum);
            }
          }
          mesh.joints.push_back(ids);
          mesh.weights.push_back(ws);
        }
        if (nrm.empty() && fresh)
          computeNormals(base, idx);
        if (fresh)
          readMorphTargets(mn, gm, prim, ctx, base, vc);
        hasUvs_ = hasUvs_ || !uv.empty();
        if (int image = baseColorImage(prim.material); image >= 0 && !uv.empty())
          trianglesPerImage_[image] += idx.size() / 3;

        std::string partName = prim.material >= 0 && size_t(prim.material) < model_.materials.size()
                                   ? model_.materials[size_t(prim.material)].name
                                   : "";
        if (partName.empty())
          partName = prim.material >= 0 ? "material" + std::to_string(prim.material) : "default";
        auto it = std::find(partOrder.begin(), partOrder.end(), partName);
        size_t part = size_t(it - partOrder.begin());
        if (it == partOrder.end()) {
          partOrder.push_back(partName);
          partTriangles.emplace_back();
          SkinnedMesh::Part look;
          if (prim.material >= 0 && size_t(prim.material) < model_.materials.size()) {
            const auto &mat = model_.materials[size_t(prim.material)];
            const auto &f = mat.pbrMetallicRoughness.baseColorFactor;
            if (f.size() == 4)
              look.colour = glm::vec4(float(f[0]), float(f[1]), float(f[2]), float(f[3]));
            look.seeThrough = mat.alphaMode == "MASK" || mat.alphaMode == "BLEND";
          }
          look.textured = baseColorImage(prim.material) >= 0 && !uv.empty();
          partLooks.push_back(look);
        }
        // Wound clockwise where the node's transform mirrors (glTF: its determinant sets the
        // winding): reversed, so that every triangle is counter-clockwise as drawn and the face
        // normals taken from the winding (flat shading, pose's files) face out. The normals
        // computed above read the file's winding in the node's own frame, where it is right.
        for (size_t t = 0; t < idx.size(); t += 3)
          partTriangles[part].insert(partTriangles[part].end(),
                                     {base + idx[t], base + idx[t + (mirrored ? 2 : 1)],
                                      base + idx[t + (mirrored ? 1 : 2)]});
        mirroredPrimitives += mirrored;
      }
    }
    for (size_t p = 0; p < partOrder.size(); ++p) {
      SkinnedMesh::Part part = partLooks[p];
      part.name = partOrder[p];
      part.firstIndex = uint32_t(mesh.indices.size());
      part.indexCount = uint32_t(partTriangles[p].size());
      mesh.parts.push_back(part);
      mesh.indices.insert(mesh.indices.end(), partTriangles[p].begin(), partTriangles[p].end());
    }
    warnCount("unweighted_vertices", unweighted,
              "skinned vertices had all-zero weights: each takes the influences of the nearest "
              "weighted vertex of its primitive");
    warnCount("points_or_lines_skipped", pointsOrLines,
              "primitives draw points or lines, not triangles: skipped");
    if (mesh.indices.empty())
      fail(pointsOrLines ? "mesh has no triangles: its primitives draw points or lines"
                         : "mesh has no triangles");
    if (!hasUvs_)
      mesh.uvs.clear();
    warnCount("more_than_4_influences", moreThan4,
              "vertices had more than 4 joint influences: kept the 4 largest, renormalised");
    warnCount("weights_renormalised", renormalised,
              "vertices had weights not summing to 1: renormalised");
    warnCount("duplicate_primitives_dropped", duplicatePrimitives,
              "primitives repeated another's vertices, indices and material: dropped");
    warnCount("normals_computed", missingNormals, "primitives had no NORMAL: computed from faces");
    warnCount("mirrored_winding", mirroredPrimitives,
              "primitives sit under a mirroring transform (a negative scale): their triangles, "
              "clockwise in the file as glTF has it there, are stored counter-clockwise");
  }

  // The morph targets of a primitive whose vertices were just appended at `base`: the node's
  // group of targets is made with its first primitive (names from the mesh's extras, default
  // weights from the node or the mesh); every target's offsets are stored per mesh vertex.
  void readMorphTargets(const MeshNode &mn, const tinygltf::Mesh &gm,
                        const tinygltf::Primitive &prim, const std::string &ctx, uint32_t base,
                        size_t vc) {
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
        if (accessorType(accessor, actx) != TINYGLTF_TYPE_VEC3 || accessorCount(accessor) != vc)
          fail(actx + ": type or count differs from POSITION");
        const auto data = readAccessor(accessor, actx);
        auto &offsets = position ? target.positions : target.normals;
        for (size_t v = 0; v < vc; ++v)
          offsets[base + v] = glm::vec3((*data)[v * 3], (*data)[v * 3 + 1], (*data)[v * 3 + 2]);
      }
    }
  }

  // What identifies a primitive's vertices: its vertex attributes' accessors, how its material
  // maps their UVs (base_colour_uv.h), and its joint (a rigid part) or its skin (one mesh bound by
  // two skins is two sets of vertices).
  std::string vertexKeyOf(const tinygltf::Primitive &prim, const MeshNode &mn) const {
    std::string key = mn.rigid >= 0 ? std::to_string(mn.rigidJoint) : "s" + std::to_string(mn.skin);
    for (const auto &[name, accessor] : prim.attributes)
      key += ";" + name + "=" + std::to_string(accessor);
    return key + ";uv=" + gltf::baseColourUv(model_, prim.material).key();
  }

  // Vertex and triangle totals from the accessors' declared counts (each distinct primitive
  // once), checked against the limits before any primitive is read.
  void checkMeshSize() const {
    std::set<std::string> vertexSets, primitives;
    uint64_t vertices = 0, triangles = 0;
    for (const auto &mn : meshNodes_)
      for (const auto &prim :
           model_.meshes[size_t(model_.nodes[size_t(mn.node)].mesh)].primitives) {
        auto pos = prim.attributes.find("POSITION");
        if (pos == prim.attributes.end() || !gltf::drawsTriangles(prim.mode))
          continue; // the reading loop names it or skips it
        const std::string key = vertexKeyOf(prim, mn);
        const uint64_t vc = accessorCount(pos->second);
        if (!primitives
                 .insert(key + "|" + std::to_string(prim.indices) + "|" +
                         std::to_string(prim.material))
                 .second)
          continue;
        if (vertexSets.insert(key).second)
          vertices += vc;
        triangles +=
            gltf::triangleCount(prim.mode, prim.indices >= 0 ? accessorCount(prim.indices) : vc);
      }
    if (vertices > limits::kVertices)
      fail("the meshes hold " + std::to_string(vertices) + " vertices, over the limit of " +
           std::to_string(limits::kVertices));
    if (triangles > limits::kTriangles)
      fail("the meshes hold " + std::to_string(triangles) + " triangles, over the limit of " +
           std::to_string(limits::kTriangles));
  }

  void computeNormals(uint32_t base, const std::vector<uint32_t> &idx) {
    auto &m = out_.mesh;
    for (size_t t = 0; t + 2 < idx.size(); t += 3) {
      glm::vec3 a = m.positions[base + idx[t]], b = m.positions[base + idx[t + 1]],
                c = m.positions[base + idx[t + 2]];
      glm::vec3 n = glm::cross(b - a, c - a);
      for (int k = 0; k < 3; ++k)
        m.normals[base + idx[t + size_t(k)]] += n;
    }
    for (size_t v = base; v < m.normals.size(); ++v) {
      float len = glm::length(m.normals[v]);
      m.normals[v] = len > 0 ? m.normals[v] / len : glm::vec3(0, 1, 0);
    }
  }

  // --- animations ------------------------------------------------------------------------

  int baseColorImage(int material) const {
    if (material < 0 || size_t(material) >= model_.materials.size())
      return -1;
    int texture = model_.materials[size_t(material)].pbrMetallicRoughness.baseColorTexture.index;
    if (texture < 0 || size_t(texture) >= model_.textures.size())
      return -1;
    // EXT_texture_webp names its WebP image apart (`source` is then an optional fallback, or
    // absent): the WebP one, which the decoder reads like any other.
    const auto &t = model_.textures[size_t(texture)];
    int image = t.source;
    if (const auto webp = t.extensions.find("EXT_texture_webp"); webp != t.extensions.end())
      if (webp->second.Has("source") && webp->second.Get("source").IsNumber())
        image = webp->second.Get("source").GetNumberAsInt();
    return image >= 0 && size_t(image) < model_.images.size() ? image : -1;
  }

  // The base-colour image covering the most triangles becomes the pack's diffuse texture.
  void readDiffuseTexture() {
    if (trianglesPerImage_.empty())
      return;
    auto best = std::max_element(trianglesPerImage_.begin(), trianglesPerImage_.end(),
                                 [](auto &a, auto &b) { return a.second < b.second; });
    int image = best->first;
    if (trianglesPerImage_.size() > 1)
      reporter_.warn("several_diffuse_textures",
                     std::to_string(trianglesPerImage_.size()) +
                         " base-colour textures: a pack holds one, kept image " +
                         std::to_string(image) + " (the one covering most triangles)",
                     trianglesPerImage_.size());
    auto warn = [&](const std::string &why) {
      reporter_.warn("diffuse_texture_skipped", "image " + std::to_string(image) + ": " + why +
                                                    ": baked without a diffuse texture");
    };
    stage_ = "decoding image " + std::to_string(image);
    auto it = encodedImages_.find(image);
    if (it == encodedImages_.end())
      return warn("no image data");
    const std::string &mime = model_.images[size_t(image)].mimeType;
    const std::string name = mime == "image/jpeg"   ? "image.jpg"
                             : mime == "image/webp" ? "image.webp"
                                                    : "image.png";
    pack::Image decoded;
    std::string why;
    if (!images::decode(it->second, name, kMaxTextureSide, decoded, why))
      return warn(why);
    const std::vector<uint8_t> &pixels = decoded.bytes;
    DiffuseTexture t{int(decoded.width), int(decoded.height), {}};
    t.rgba.resize(size_t(t.width) * size_t(t.height) * 4);
    for (size_t p = 0; p < size_t(t.width) * size_t(t.height); ++p)
      for (size_t k = 0; k < 4; ++k) {
        size_t c = size_t(decoded.channels);
        // Grey, grey+alpha, RGB and RGBA sources all become RGBA.
        uint8_t v = k < 3 ? pixels[p * c + (c >= 3 ? k : 0)]
                          : (c == 2 || c == 4 ? pixels[p * c + c - 1] : 255);
        t.rgba[p * 4 + k] = v;
      }
    out_.diffuse = std::move(t);
  }

  void readAnimations() {
    size_t strayWeightChannels = 0, duplicateTargets = 0;
    std::string firstDuplicate;
    for (size_t ai = 0; ai < model_.animations.size(); ++ai) {
      const auto &anim = model_.animations[ai];
      AnimationClip clip;
      clip.name = anim.name.empty() ? "clip" + std::to_string(ai) : anim.name;
      std::string actx = "animation '" + clip.name + "'";
      bool first = true;
      std::map<std::pair<int, std::string>, size_t> channelOf; // per target, its first channel
      for (size_t ci = 0; ci < anim.channels.size(); ++ci) {
        const auto &ch = anim.channels[ci];
        std::string ctx = actx + ", channel " + std::to_string(ci);
        Channel out;
        if (ch.target_node < 0 || size_t(ch.target_node) >= out_.nodes.size())
          fail(ctx + ": target node " + std::to_string(ch.target_node) + " does not exist");
        // The specification allows a target once per animation; readers differ on a second
        // (three.js blends the two, others take the last): the first is kept, with a warning.
        if (const auto [at, fresh] = channelOf.try_emplace({ch.target_node, ch.target_path}, ci);
            !fresh) {
          if (duplicateTargets++ == 0)
            firstDuplicate = ctx + " animates node " + std::to_string(ch.target_node) + "'s " +
                             ch.target_path + " as channel " + std::to_string(at->second) + " does";
          continue;
        }
        out.node = ch.target_node;
        if (ch.target_path == "weights") {
          const MorphGroup *group = out_.morphGroupOf(ch.target_node);
          if (!group) { // no baked mesh of this node has targets
            ++strayWeightChannels;
            continue;
          }
          out.components = group->count;
        }
        if (ch.target_path == "translation")
          out.path = ChannelPath::Translation;
        else if (ch.target_path == "rotation")
          out.path = ChannelPath::Rotation;
        else if (ch.target_path == "scale")
          out.path = ChannelPath::Scale;
        else if (ch.target_path == "weights")
          out.path = ChannelPath::Weights;
        else
          fail(ctx + ": unknown target path '" + ch.target_path + "'");
        if (out_.nodes[size_t(out.node)].hasMatrix && out.path != ChannelPath::Weights)
          fail(ctx + ": animates node " + std::to_string(out.node) + " which has a matrix");
        if (ch.sampler < 0 || size_t(ch.sampler) >= anim.samplers.size())
          fail(ctx + ": sampler " + std::to_string(ch.sampler) + " does not exist");
        const auto &s = anim.samplers[size_t(ch.sampler)];
        if (s.interpolation == "STEP")
          out.interpolation = Interpolation::Step;
        else if (s.interpolation == "CUBICSPLINE")
          out.interpolation = Interpolation::CubicSpline;
        else if (s.interpolation == "LINEAR" || s.interpolation.empty())
          out.interpolation = Interpolation::Linear;
        else
          fail(ctx + ": unknown interpolation '" + s.interpolation + "'");
        out.times = *readAccessor(s.input, ctx + " input");
        if (out.times.empty())
          fail(ctx + ": sampler has no keyframes");
        // Two keys at one time are read as a step (the later holds from that time on), with a
        // warning: the specification asks for strictly increasing times.
        size_t steps = 0;
        for (size_t k = 1; k < out.times.size(); ++k)
          if (out.times[k] == out.times[k - 1])
            ++steps;
          else if (!(out.times[k] > out.times[k - 1]))
            fail(ctx + " input: key times decrease at key " + std::to_string(k));
        if (steps)
          reporter_.warn("keys_at_one_time",
                         ctx + ": " + std::to_string(steps) +
                             " pairs of keys share a time: read as steps (the later key holds "
                             "from that time)",
                         steps);
        out.values = *readAccessor(s.output, ctx + " output");
        if (out.path == ChannelPath::Rotation)
          out.components = 4;
        const size_t comps = out.components;
        size_t per = out.interpolation == Interpolation::CubicSpline ? 3 : 1;
        if (out.values.size() != out.times.size() * comps * per)
          fail(ctx + " output: " + std::to_string(out.values.size()) + " values for " +
               std::to_string(out.times.size()) + " keys of " + std::to_string(comps * per));
        // Rotation keys are unit quaternions; quantized ones (gltfpack's 16-bit) are off by up to
        // 3e-5, and slerp between keys as they are turns the wrong amount: normalized here (keys
        // within 1e-6 are left as they are; a cubic spline's values hold tangents).
        for (size_t k = 0; out.path == ChannelPath::Rotation && per == 1 && k < out.times.size();
             ++k) {
          double *q = &out.values[k * 4];
          const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
          if (n > 0 && std::abs(n - 1) > 1e-6)
            for (int c = 0; c < 4; ++c)
              q[c] /= n;
        }
        clip.start = first ? out.times.front() : std::min(clip.start, out.times.front());
        clip.end = first ? out.times.back() : std::max(clip.end, out.times.back());
        first = false;
        clip.channels.push_back(std::move(out));
      }
      if (!clip.channels.empty())
        out_.clips.push_back(std::move(clip));
    }
    makeNamesUnique(out_.clips, "duplicate_clip_names", "clips", "clips are chosen by name");
    warnCount("morph_weights_without_targets", strayWeightChannels,
              "morph-weight channels animate nodes whose baked mesh has no morph targets: ignored");
    warnCount("duplicate_channel_targets", duplicateTargets,
              "channels animate a target an earlier channel of their animation does (the "
              "specification allows one): ignored, the first kept (first: " +
                  firstDuplicate + ")");
  }

  std::string path_;
  std::string stage_; // what the import is doing, for an out-of-memory error
  Reporter &reporter_;
  std::map<std::pair<int, bool>, std::shared_ptr<const std::vector<double>>> accessorCache_;
  Model model_;
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

} // namespace

Character importGltf(const std::string &path, const ImportOptions &options, Reporter &reporter) {
  return Importer(path, reporter).run(options);
}

} // namespace crowd
