#include "importer.h"

#include <algorithm>
#include <cstring>
#include <filesystem>

#include "crowd/bake/input_files.h"
#include "crowd/support/json_checker.h"
#include "gltf_schema.h"
#include "meshopt_views.h"

namespace crowd {
namespace gltf {
namespace {

std::string oneLine(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' '))
    s.pop_back();
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

// Where tinygltf hands each image over: `model` as parsed so far (its buffers and views first).
struct ImageSink {
  EncodedImages *images;
  const tinygltf::Model *model;
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

// tinygltf reads external buffers and images through these callbacks, so every URI goes
// through resolveNamedInput and readInputFile; the first refusal becomes the import's error.
struct Confinement {
  const std::string *gltf;
  const InputPolicy *policy;
  std::string problem;
  std::vector<std::string> read; // every external file read, in order
};
constexpr const char *kRefused = "\x01refused";
std::string expandUri(const std::string &uri, void *user) {
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
bool uriExists(const std::string &path, void *) {
  std::error_code ec;
  return path != kRefused && std::filesystem::exists(path, ec);
}
bool readUri(std::vector<unsigned char> *out, std::string *err, const std::string &path,
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
bool noWrite(std::string *, const std::string &, const std::vector<unsigned char> &, void *) {
  return false;
}

} // namespace

Character Importer::run(const ImportOptions &options) {
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

void Importer::load(const InputPolicy &policy) {
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
  support::checkJsonDepth(json, path_);
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

} // namespace gltf

Character importGltf(const std::string &path, const ImportOptions &options, Reporter &reporter) {
  return gltf::Importer(path, reporter).run(options);
}

} // namespace crowd
