#include "gltf_schema.h"

#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "crowd/formats/error.h"

namespace crowd {

namespace {

using nlohmann::json;

// Index properties and the top-level array they point into (an object under one of these keys,
// like a sparse accessor's "indices", is walked instead). A channel's "sampler" points into its
// animation and is checked by the importer; a texture's is checked against /samplers below.
const std::map<std::string, std::string> kIndexOf = {
    {"mesh", "meshes"},        {"skin", "skins"},        {"camera", "cameras"},
    {"skeleton", "nodes"},     {"node", "nodes"},        {"scene", "scenes"},
    {"material", "materials"}, {"indices", "accessors"}, {"inverseBindMatrices", "accessors"},
    {"input", "accessors"},    {"output", "accessors"},  {"bufferView", "bufferViews"},
    {"buffer", "buffers"},     {"source", "images"},     {"index", "textures"}};
// Lists of indices.
const std::map<std::string, std::string> kIndexListOf = {
    {"children", "nodes"}, {"nodes", "nodes"}, {"joints", "nodes"}};
// Counts, offsets and enumerations: non-negative integers.
const std::set<std::string> kUnsigned = {"byteOffset",    "byteStride", "byteLength", "count",
                                         "componentType", "mode",       "texCoord"};
const std::set<std::string> kStrings = {"type", "path", "interpolation", "mimeType",
                                        "uri",  "name", "alphaMode"};

class Checker {
public:
  Checker(const json &root, const std::string &path) : root_(root), path_(path) {}

  void walk(const json &j, const std::string &at, const std::string &parentKey) {
    if (j.is_object()) {
      for (const auto &[key, value] : j.items()) {
        if (key == "extensions" || key == "extras")
          continue; // free-form
        const std::string here = at + "/" + key;
        if (parentKey == "targets") // a morph target: attribute name -> accessor
          index(value, here, "accessors");
        else if (auto it = kIndexOf.find(key); it != kIndexOf.end() && !value.is_object())
          index(value, here, it->second);
        else if (auto list = kIndexListOf.find(key); list != kIndexListOf.end() && !at.empty()) {
          if (!value.is_array())
            fail(here, "expected a list of indices");
          for (size_t i = 0; i < value.size(); ++i)
            index(value[i], here + "/" + std::to_string(i), list->second);
        } else if (kUnsigned.count(key) && !value.is_number_unsigned())
          fail(here, "expected a non-negative integer, got " + value.dump().substr(0, 40));
        else if (kStrings.count(key) && !value.is_string())
          fail(here, "expected a string, got " + value.dump().substr(0, 40));
        else if (key == "attributes" && value.is_object())
          for (const auto &[name, acc] : value.items())
            index(acc, here + "/" + name, "accessors");
        else if (key == "sampler" && parentKey == "textures")
          index(value, here, "samplers");
        else
          walk(value, here, key);
      }
      if (parentKey == "channels") {
        if (!j.contains("target") || !j["target"].is_object() || !j["target"].contains("path"))
          fail(at, "a channel needs a target with a path");
      }
    } else if (j.is_array()) {
      for (size_t i = 0; i < j.size(); ++i)
        walk(j[i], at + "/" + std::to_string(i), parentKey);
    }
  }

private:
  void index(const json &v, const std::string &at, const std::string &array) {
    if (!v.is_number_unsigned())
      fail(at, "expected an index into /" + array + ", got " + v.dump().substr(0, 40));
    const uint64_t i = v.get<uint64_t>();
    const auto it = root_.find(array);
    const size_t size = it != root_.end() && it->is_array() ? it->size() : 0;
    if (i >= size)
      fail(at, "index " + std::to_string(i) + " names nothing: /" + array + " has " +
                   std::to_string(size) + " elements");
  }
  [[noreturn]] void fail(const std::string &at, const std::string &what) const {
    throw Error(path_ + ": " + (at.empty() ? "/" : at) + ": " + what);
  }

  const json &root_;
  const std::string &path_;
};

} // namespace

void checkGltfJson(std::string_view text, const std::string &path) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception &) {
    return; // tinygltf reports syntax errors with its own words
  }
  if (!root.is_object())
    throw Error(path + ": the glTF JSON is not an object");
  Checker(root, path).walk(root, "", "");
  // Before tinygltf, which fails a compressed file on its placeholder buffer in other words.
  if (const auto it = root.find("extensionsRequired"); it != root.end() && it->is_array())
    for (const json &ext : *it) {
      const std::string name = ext.is_string() ? ext.get<std::string>() : ext.dump();
      if (kSupportedRequired.count(name))
        continue;
      const bool draco = name == "KHR_draco_mesh_compression";
      const bool texture = name == "KHR_texture_basisu" || name == "EXT_texture_avif";
      throw Error(path + ": unsupported required extension " + name +
                  (draco     ? " (Draco-compressed geometry: export without Draco, or compress "
                               "with meshopt, gltfpack -c, which crowdbake decodes)"
                   : texture ? " (textures crowdbake does not decode: export PNG, JPEG or WebP "
                               "textures, e.g. gltfpack without -tc)"
                             : ""));
    }
}

} // namespace crowd
