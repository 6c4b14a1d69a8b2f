#include "crowd/bake/provenance.h"

#include <filesystem>

#include "crowd/bake/input_files.h"

#include "crowd/formats/error.h"

namespace crowd {

pack::Provenance makeProvenance(const std::vector<std::string> &inputs,
                                std::vector<std::pair<std::string, std::string>> settings) {
  pack::Provenance p;
  p.bakerVersion = kBakerVersion;
  p.settings = std::move(settings);
  for (const auto &path : inputs) {
    const FileHash h = hashFile(path); // streamed: an input is never held whole for its hash
    p.inputs.push_back({std::filesystem::path(path).filename().string(), h.size, h.hash});
  }
  return p;
}

} // namespace crowd
