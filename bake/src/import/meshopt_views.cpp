#include "meshopt_views.h"

#include <cstring>
#include <map>
#include <set>

#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include "crowd/bake/glb.h"
#include "crowd/formats/error.h"
#include "crowd/formats/limits.h"

namespace crowd {

namespace {

using json = nlohmann::json;

const char *const kExtensions[] = {"EXT_meshopt_compression", "KHR_meshopt_compression"};

// The newest stream version the linked meshoptimizer decodes: vertex streams gained version 1
// in meshoptimizer 0.23; index and sequence streams have had version 1 since 0.14.
constexpr int kVertexVersion = MESHOPTIMIZER_VERSION >= 230 ? 1 : 0;
constexpr int kIndexVersion = 1;

std::string meshoptVersion() { // 180: 0.18
  return std::to_string(MESHOPTIMIZER_VERSION / 1000) + "." +
         std::to_string(MESHOPTIMIZER_VERSION % 1000 / 10);
}

struct Glb {
  json gltf;
  std::vector<uint8_t> bin;
  bool hasBin = false;
};

Glb parse(const std::vector<uint8_t> &bytes, const std::string &path) {
  GlbParts parts = glbParts(bytes, path);
  Glb g;
  g.bin = std::move(parts.bin);
  g.hasBin = parts.hasBin;
  try {
    g.gltf = json::parse(parts.json);
  } catch (const json::exception &e) {
    throw Error(path + ": the glTF JSON does not parse: " + e.what());
  }
  return g;
}

uint64_t field(const json &object, const char *key, uint64_t fallback, const std::string &where) {
  const auto it = object.find(key);
  if (it == object.end())
    return fallback;
  if (!it->is_number_unsigned())
    throw Error(where + ": '" + key + "' is not a non-negative integer");
  return it->get<uint64_t>();
}

// One compressed view decoded: `source` the compressed bytes, `ext` the extension's object,
// `room` the bytes the decoded views may still take (checked before the output is allocated:
// count and byteStride alone ask for up to 4 GiB).
std::vector<uint8_t> decodeView(const json &ext, const std::vector<uint8_t> &source, uint64_t room,
                                const std::string &where) {
  const uint64_t count = field(ext, "count", UINT64_MAX, where);
  const uint64_t stride = field(ext, "byteStride", 0, where);
  const std::string mode = ext.value("mode", std::string());
  const std::string filter = ext.value("filter", std::string("NONE"));
  if (count == UINT64_MAX || count == 0 || count > limits::kAccessorElements)
    throw Error(where + ": count " + (count == UINT64_MAX ? "missing" : std::to_string(count)) +
                " (1.." + std::to_string(limits::kAccessorElements) + ")");
  if (source.empty())
    throw Error(where + ": no compressed bytes");
  // The stream's first byte: its kind in the high nibble, its version in the low one.
  const int kind = source[0] >> 4, version = source[0] & 15;
  const int expectKind = mode == "ATTRIBUTES"  ? 0xA
                         : mode == "TRIANGLES" ? 0xE
                         : mode == "INDICES"   ? 0xD
                                               : -1;
  if (expectKind < 0)
    throw Error(where + ": unknown mode '" + mode + "' (ATTRIBUTES, TRIANGLES or INDICES)");
  if (stride == 0 || stride > 256 ||
      (mode == "ATTRIBUTES" ? stride % 4 : stride != 2 && stride != 4))
    throw Error(where + ": byteStride " + std::to_string(stride) + " does not suit mode '" + mode +
                "' (attributes: a multiple of 4 up to 256; indices: 2 or 4)");
  if (kind != expectKind)
    throw Error(where + ": the compressed bytes are not a meshopt " + mode + " stream");
  const int newest = mode == "ATTRIBUTES" ? kVertexVersion : kIndexVersion;
  if (version > newest)
    throw Error(where + ": its " + mode + " stream is of codec version " + std::to_string(version) +
                ", which the linked meshoptimizer " + meshoptVersion() +
                " cannot decode (it reads up to version " + std::to_string(newest) +
                "): compress with an older gltfpack, or not at all");
  if (count * stride > room)
    throw Error(where + ": " + std::to_string(count) + " elements of " + std::to_string(stride) +
                " bytes take the decoded views over " +
                std::to_string(limits::kInputFileBytes >> 20) + " MiB");
  std::vector<uint8_t> out(count * stride);
  int rc = 0;
  if (mode == "ATTRIBUTES")
    rc = meshopt_decodeVertexBuffer(out.data(), count, stride, source.data(), source.size());
  else if (mode == "TRIANGLES") {
    if (count % 3 != 0)
      throw Error(where + ": TRIANGLES with a count of " + std::to_string(count) +
                  ", not whole triangles");
    rc = meshopt_decodeIndexBuffer(out.data(), count, stride, source.data(), source.size());
  } else
    rc = meshopt_decodeIndexSequence(out.data(), count, stride, source.data(), source.size());
  if (rc != 0)
    throw Error(where + ": the " + mode + " stream does not decode (" + std::to_string(count) +
                " elements of " + std::to_string(stride) +
                " bytes): corrupted, or its count or "
                "byteStride is wrong");
  if (filter == "NONE")
    return out;
  if (mode != "ATTRIBUTES")
    throw Error(where + ": filter " + filter + " on " + mode + " (filters apply to attributes)");
  if (filter == "OCTAHEDRAL" && (stride == 4 || stride == 8))
    meshopt_decodeFilterOct(out.data(), count, stride);
  else if (filter == "QUATERNION" && stride == 8)
    meshopt_decodeFilterQuat(out.data(), count, stride);
  else if (filter == "EXPONENTIAL")
    meshopt_decodeFilterExp(out.data(), count, stride);
  else if (filter == "OCTAHEDRAL" || filter == "QUATERNION")
    throw Error(where + ": filter " + filter + " with byteStride " + std::to_string(stride) +
                " (octahedral: 4 or 8; quaternion: 8)");
  else
    throw Error(where + ": filter '" + filter + "', which the linked meshoptimizer " +
                meshoptVersion() + " does not decode (NONE, OCTAHEDRAL, QUATERNION, EXPONENTIAL)");
  return out;
}

// The glTF's buffers' bytes, each read once: the GLB's binary chunk (buffer 0 without a URI) or
// the file its URI names.
class Buffers {
public:
  Buffers(const Glb &g, const ReadBufferUri &readUri) : g_(g), readUri_(readUri) {}
  size_t count() const {
    return g_.gltf.contains("buffers") && g_.gltf["buffers"].is_array() ? g_.gltf["buffers"].size()
                                                                        : 0;
  }
  const std::vector<uint8_t> &bytes(size_t k, const std::string &where) {
    if (const auto it = data_.find(k); it != data_.end())
      return it->second;
    const json &buffer = g_.gltf["buffers"][k];
    if (!buffer.contains("uri")) {
      if (k != 0 || !g_.hasBin)
        throw Error(where + ": its source buffer " + std::to_string(k) +
                    " has no data (no URI, and not the GLB's binary chunk)");
      return data_[k] = g_.bin;
    }
    const std::string uri = buffer["uri"].is_string() ? buffer["uri"].get<std::string>() : "";
    if (uri.rfind("data:", 0) == 0)
      throw Error(where + ": its source buffer " + std::to_string(k) +
                  " is a data: URI; crowdbake decodes compressed views from a .glb or a .bin file");
    return data_[k] = readUri_(uri);
  }

private:
  const Glb &g_;
  const ReadBufferUri &readUri_;
  std::map<size_t, std::vector<uint8_t>> data_;
};

// Decodes view `v`'s compressed bytes (extension `name`) onto the end of `decoded`, 4-aligned,
// and points the view at them in buffer 0, the extension gone.
void decodeOne(json &view, size_t v, const char *name, Buffers &buffers,
               std::vector<uint8_t> &decoded, const std::string &path) {
  const std::string where = path + ": bufferViews[" + std::to_string(v) + "] " + name;
  const json &ext = view["extensions"][name];
  if (!ext.is_object())
    throw Error(where + ": not an object");
  const uint64_t buffer = field(ext, "buffer", UINT64_MAX, where);
  const uint64_t offset = field(ext, "byteOffset", 0, where);
  const uint64_t length = field(ext, "byteLength", UINT64_MAX, where);
  if (buffer >= buffers.count())
    throw Error(where + ": buffer " + std::to_string(buffer) + " does not exist");
  const std::vector<uint8_t> &source = buffers.bytes(buffer, where);
  if (length == UINT64_MAX || offset > source.size() || length > source.size() - offset)
    throw Error(where + ": bytes [" + std::to_string(offset) + ", +" +
                (length == UINT64_MAX ? std::string("?") : std::to_string(length)) +
                ") lie outside its buffer of " + std::to_string(source.size()) + " bytes");
  decoded.resize((decoded.size() + 3) / 4 * 4, 0);
  const uint64_t room =
      limits::kInputFileBytes - std::min<uint64_t>(decoded.size(), limits::kInputFileBytes);
  const std::vector<uint8_t> out = decodeView(
      ext,
      std::vector<uint8_t>(source.begin() + long(offset), source.begin() + long(offset + length)),
      room, where);
  view["buffer"] = 0;
  view["byteOffset"] = decoded.size();
  view["byteLength"] = out.size();
  if (ext.value("mode", std::string()) != "ATTRIBUTES")
    view.erase("byteStride");
  decoded.insert(decoded.end(), out.begin(), out.end());
  view["extensions"].erase(name);
}

// Buffer 0 becomes the binary chunk of `bytes` bytes: without one before, a new buffer 0, every
// other buffer moving up one (the decoded views already point at 0). A fallback buffer (no data:
// the compressed views were its only readers) becomes one zero byte that no view reads. The
// extension leaves the used and required lists.
void rewriteBuffers(json &gltf, bool newBufferZero, const std::set<size_t> &decodedViews,
                    size_t bytes) {
  if (newBufferZero) {
    json list = json::array({json::object()});
    for (auto &b : gltf["buffers"])
      list.push_back(b);
    gltf["buffers"] = list;
    for (size_t v = 0; v < gltf["bufferViews"].size(); ++v)
      if (json &view = gltf["bufferViews"][v];
          !decodedViews.count(v) && view.contains("buffer") && view["buffer"].is_number_unsigned())
        view["buffer"] = view["buffer"].get<uint64_t>() + 1;
  }
  for (size_t k = 1; k < gltf["buffers"].size(); ++k)
    if (json &b = gltf["buffers"][k]; b.is_object() && !b.contains("uri"))
      b = {{"byteLength", 1}, {"uri", "data:application/octet-stream;base64,AA=="}};
  gltf["buffers"][0] = {{"byteLength", bytes}};
  for (const char *list : {"extensionsUsed", "extensionsRequired"})
    if (gltf.contains(list) && gltf[list].is_array()) {
      json kept = json::array();
      for (const auto &e : gltf[list])
        if (!(e == kExtensions[0] || e == kExtensions[1]))
          kept.push_back(e);
      gltf[list] = kept;
    }
}

} // namespace

bool decodeMeshoptViews(std::vector<uint8_t> &bytes, const std::string &path,
                        const ReadBufferUri &readUri) {
  // A cheap look first: most files never name the extension.
  const std::string_view all(reinterpret_cast<const char *>(bytes.data()), bytes.size());
  if (all.find("meshopt_compression") == std::string_view::npos)
    return false;
  Glb g = parse(bytes, path);
  json &gltf = g.gltf;
  if (!gltf.is_object() || !gltf.contains("bufferViews") || !gltf["bufferViews"].is_array())
    return false;
  Buffers buffers(g, readUri);
  // The decoded views go after the binary chunk (buffer 0 in the GLB written).
  const bool appendToBin = g.hasBin && buffers.count() > 0 && !gltf["buffers"][0].contains("uri");
  std::vector<uint8_t> decoded = appendToBin ? g.bin : std::vector<uint8_t>{};
  std::set<size_t> decodedViews;
  for (size_t v = 0; v < gltf["bufferViews"].size(); ++v) {
    json &view = gltf["bufferViews"][v];
    if (!view.is_object() || !view.contains("extensions"))
      continue;
    for (const char *name : kExtensions)
      if (view["extensions"].contains(name)) {
        decodeOne(view, v, name, buffers, decoded, path);
        decodedViews.insert(v);
      }
    if (view["extensions"].empty())
      view.erase("extensions");
  }
  if (decodedViews.empty())
    return false;
  rewriteBuffers(gltf, !appendToBin, decodedViews, decoded.size());
  g.bin = std::move(decoded);
  g.hasBin = true;
  bytes = glbBytes(g.gltf, g.bin);
  return true;
}

} // namespace crowd
