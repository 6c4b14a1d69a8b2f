#include "crowd/bake/provenance.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <OpenImageIO/hash.h>

#include "crowd/formats/error.h"

namespace crowd {

pack::Provenance makeProvenance(const std::vector<std::string> &inputs,
                                std::vector<std::pair<std::string, std::string>> settings) {
  pack::Provenance p;
  p.bakerVersion = kBakerVersion;
  p.settings = std::move(settings);
  for (const auto &path : inputs) {
    std::ifstream f(path, std::ios::binary);
    if (!f)
      throw Error(path + ": cannot open file");
    std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx",
                  (unsigned long long)OIIO::farmhash::Fingerprint64(bytes.data(), bytes.size()));
    p.inputs.push_back({std::filesystem::path(path).filename().string(), bytes.size(),
                        std::string("farmhash64:") + hex});
  }
  return p;
}

} // namespace crowd
