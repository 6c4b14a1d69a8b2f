#include "crowd/support/images.h"

#include <dlfcn.h>

#include <filesystem>
#include <mutex>

#include "crowd/formats/error.h"
#include "image_codec.h"

namespace crowd::images {
namespace {

// The module's table, loaded once: from the running program's folder (where the build puts
// it), else the installed layout's <libdir>/crowdbake seen from <bindir>. Throws Error naming
// both.
const Codec &codec() {
  static std::once_flag once;
  static const Codec *table = nullptr;
  static std::string failure;
  std::call_once(once, [] {
    std::error_code ec;
    const auto self = std::filesystem::read_symlink("/proc/self/exe", ec).parent_path();
    for (const auto &dir : {self, self / CROWD_MODULE_FROM_BIN}) {
      const std::string path = (dir / kImageModule).string();
      void *module = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!module) {
        failure += std::string(failure.empty() ? "" : "; ") + dlerror();
        continue;
      }
      using Entry = const Codec *(*)();
      if (auto entry = reinterpret_cast<Entry>(dlsym(module, "crowd_image_codec"))) {
        table = entry();
        return;
      }
      failure += "; " + path + ": no crowd_image_codec";
    }
  });
  if (!table)
    throw Error(std::string("images: cannot load the OpenImageIO module ") + kImageModule + " (" +
                failure + ")");
  return *table;
}

} // namespace

bool decode(const std::vector<uint8_t> &bytes, const std::string &name, int maxSide,
            pack::Image &out, std::string &why) {
  const Codec *c = nullptr;
  try { // a module that cannot load is one more reason not to decode, as the header says
    c = &codec();
  } catch (const Error &e) {
    why = e.what();
    return false;
  }
  return c->decode(bytes, name, maxSide, out, why);
}

void write(const std::string &path, const pack::Image &image) {
  std::string why;
  if (!codec().write(path, image, why))
    throw Error(path + ": cannot write image: " + why);
}

std::vector<uint8_t> encodePng(const pack::Image &image) {
  std::vector<uint8_t> bytes;
  std::string why;
  if (!codec().encodePng(image, bytes, why))
    throw Error("cannot encode a PNG: " + why);
  return bytes;
}

} // namespace crowd::images
