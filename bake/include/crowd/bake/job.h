// Jobs: every bake of a character build as a unit of work that a worker (a local thread or a
// Slurm array task) can run alone. A job is keyed by its content (input file hashes, canonical
// settings, the keys of the jobs it reads, the baker version) and produces a Part: chunks for
// the character pack and figures for the build report. Kinds register once in job.cpp.
#pragma once
#include "crowd/bake/input_files.h"
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "crowd/bake/manifest.h"
#include "crowd/bake/report.h"

namespace crowd {

// What a job produced: pack chunks (in the order the pack will hold them) and its figures
// (times, sizes, errors and warnings: {"warnings": [...]}), which never enter a pack.
struct Part {
  struct Chunk {
    uint32_t type = 0, version = 0;
    std::vector<uint8_t> payload;
  };
  std::vector<Chunk> chunks;
  nlohmann::ordered_json figures = nlohmann::ordered_json::object();
};

// A part as bytes (a crowdpack container: its chunks and a FIGS chunk of JSON), so that the
// cache checks it with the reader's checksums.
std::vector<uint8_t> partBytes(const Part &part);
Part partFromBytes(std::vector<uint8_t> bytes, const std::string &name); // throws on damage

struct Job {
  std::string kind; // "mesh", "impostor", "cloth", "link": see jobKinds()
  std::shared_ptr<const CharacterManifest> character;
  std::string clip, outfit;        // impostor jobs: the pair they draw; cloth jobs: the loop's
  size_t cloth = 0;                // cloth jobs: the manifest's entry
  std::vector<std::string> files;  // inputs whose bytes the job reads
  std::vector<FileHash> hashes;    // per file (set by keyJobs)
  std::vector<size_t> deps;        // jobs whose parts it reads, by index in the plan
  nlohmann::ordered_json settings; // canonical: everything besides inputs that shapes the part
  std::string key;                 // content key (set by keyJobs)
  std::string label() const;       // "soldier: impostor walk/dress", for people
};

// How a worker runs a job: the bound on the job's own worker threads, and where its progress
// lines go (Reporter::step; nowhere when empty).
struct JobContext {
  int threads = 0;
  Reporter::Listener progress;
};

// Runs a job on its dependencies' parts.
using JobFunction = Part (*)(const Job &, const std::vector<const Part *> &deps,
                             const JobContext &context);
struct JobKind {
  const char *name;
  JobFunction run;
};
const std::vector<JobKind> &jobKinds();
Part runJob(const Job &job, const std::vector<const Part *> &deps, const JobContext &context);

// Every job of a character: its mesh (outfits, LOD, animation), one per impostor pair, one per
// cloth loop, and the link that writes its pack (always last). Indices in deps are offset by
// `base`.
std::vector<Job> planCharacter(std::shared_ptr<const CharacterManifest> character, size_t base);

// A pack's PROV chunk for a job: the baker version, the command, the job's canonical settings and
// each input file's name, size and hash (as keyJobs hashed them).
Part::Chunk provenanceChunk(const Job &job, const std::string &command);

// The pack bytes of a link job's part.
std::vector<uint8_t> characterPackBytes(const Part &link);

} // namespace crowd
