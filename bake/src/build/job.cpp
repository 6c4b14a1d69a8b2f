#include "crowd/bake/job.h"

#include <filesystem>

#include "crowd/bake/provenance.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/container.h"
#include "crowd/formats/error.h"

namespace crowd {

namespace {
constexpr uint32_t kFigures = pack::fourcc("FIGS"); // a part's figures (JSON), never in a pack
}

// The job kinds, each a function in its bake's folder (<bake>_job.cpp; the mesh and link jobs in
// build/character_jobs.cpp). A new bake adds its function and one line here.
Part meshJob(const Job &, const std::vector<const Part *> &, const JobContext &);
Part impostorJob(const Job &, const std::vector<const Part *> &, const JobContext &);
Part clothJob(const Job &, const std::vector<const Part *> &, const JobContext &);
Part terrainJob(const Job &, const std::vector<const Part *> &, const JobContext &);
Part linkJob(const Job &, const std::vector<const Part *> &, const JobContext &);

const std::vector<JobKind> &jobKinds() {
  static const std::vector<JobKind> kinds = {
      {"mesh", meshJob},       {"impostor", impostorJob}, {"cloth", clothJob},
      {"terrain", terrainJob}, {"link", linkJob},
  };
  return kinds;
}

Part runJob(const Job &job, const std::vector<const Part *> &deps, const JobContext &context) {
  for (const auto &k : jobKinds())
    if (job.kind == k.name)
      return k.run(job, deps, context);
  throw Error("unknown job kind '" + job.kind + "'");
}

std::string Job::label() const {
  std::string s = character->name + ": " + kind;
  if (kind == "impostor")
    s += " " + (clip.empty() ? std::string("(first clip)") : clip) +
         (outfit.empty() ? "" : "/" + outfit);
  if (kind == "cloth") {
    const auto &c = character->cloth.at(cloth);
    s += " " + c.outfit + "/" + c.garment + " over " + c.clip;
  }
  return s;
}

std::vector<uint8_t> partBytes(const Part &part) {
  pack::Writer w;
  for (const auto &c : part.chunks)
    w.add(c.type, c.version, c.payload);
  const std::string figures = part.figures.dump();
  w.add(kFigures, 1, {figures.begin(), figures.end()});
  return w.bytes();
}

Part partFromBytes(std::vector<uint8_t> bytes, const std::string &name) {
  pack::Reader reader(std::move(bytes), name);
  Part part;
  for (const auto &c : reader.chunks()) {
    auto payload = reader.payload(c);
    if (c.type != kFigures) {
      part.chunks.push_back({c.type, c.version, {payload.begin(), payload.end()}});
      continue;
    }
    try {
      part.figures = nlohmann::ordered_json::parse(payload.begin(), payload.end());
    } catch (const std::exception &e) {
      throw Error(name + ": figures are not JSON: " + e.what());
    }
  }
  return part;
}

Part::Chunk provenanceChunk(const Job &job, const std::string &command) {
  pack::Provenance prov;
  prov.bakerVersion = kBakerVersion;
  // Settings that add figures or a proof but change no byte (impostor "measure", the outfits'
  // hole "check") stay out, so asking for them leaves the pack as it is.
  nlohmann::ordered_json settings = job.settings;
  if (settings.contains("impostor") && settings["impostor"].is_object())
    settings["impostor"].erase("measure");
  if (settings.contains("visibility"))
    settings["visibility"].erase("check");
  prov.settings = {{"command", command}, {"character", settings.dump()}};
  for (size_t k = 0; k < job.files.size(); ++k)
    prov.inputs.push_back({std::filesystem::path(job.files[k]).filename().string(),
                           job.hashes.at(k).size, job.hashes.at(k).hash});
  return {pack::kProvenance, 1, pack::encode(prov)};
}

std::vector<uint8_t> characterPackBytes(const Part &link) {
  pack::Writer w;
  for (const auto &c : link.chunks)
    w.add(c.type, c.version, c.payload);
  return w.bytes();
}

} // namespace crowd
