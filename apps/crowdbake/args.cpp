#include "args.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <unistd.h>

#include "crowd/bake/single_job.h"
#include "crowd/formats/container.h"

namespace crowd::cli {

bool parseArgs(CLI::App &app, int argc, char **argv) {
  try {
    app.parse(argc - 1, argv + 1);
  } catch (const CLI::CallForHelp &) {
    std::cout << app.help();
    return false;
  } catch (const CLI::ParseError &e) {
    throw UsageError(std::string(e.what()) + " (see " + app.get_name() + " --help)");
  }
  return true;
}

void example(CLI::App &app, const std::string &text) { app.footer("\nexample:\n  " + text + "\n"); }

void InputArgs::add(CLI::App &app) {
  const char *group = "Untrusted input (every file read)";
  app.add_option("--asset-root", policy.assetRoot,
                 "files named by glTFs and manifests (buffers, images, bodies) must resolve "
                 "inside DIR (default: the naming file's own folder); absolute paths are "
                 "accepted inside DIR only; '..' leaving it, links out of it and non-regular "
                 "files are errors")
      ->group(group);
  app.add_option("--max-file-size", maxFileMiB_,
                 "largest input file read, in MiB, checked before reading")
      ->capture_default_str()
      ->group(group);
  app.add_option("--max-memory", limits.maxMemoryMiB,
                 "stop with an error past this resident memory, in MiB (0: 3/4 of RAM)")
      ->capture_default_str()
      ->group(group);
  app.add_option("--max-seconds", limits.maxSeconds,
                 "stop with an error after this many seconds (0: no limit); a bake stopped by "
                 "either limit writes nothing")
      ->capture_default_str()
      ->group(group);
}

void InputArgs::finish() {
  if (!(maxFileMiB_ >= 1 && maxFileMiB_ <= double(1 << 22)))
    throw UsageError("--max-file-size: must be in [1, " + std::to_string(1 << 22) + "] MiB");
  policy.maxFileBytes = uint64_t(maxFileMiB_) << 20;
  validated(policy);
  validated(limits);
}

void BakeArgs::add(CLI::App &app, const char *inputHelp) {
  app.add_option("INPUT", input, inputHelp)->required();
  app.add_option("-o,--output", output, "pack to write (written atomically)")->required();
  app.add_option("--report", report, "write the bake's figures as JSON to FILE");
  app.add_flag("-q,--quiet", quiet, "no warnings or progress on stderr");
  files.add(app);
}

std::pair<std::string, std::string> outfitNameAndFile(const std::string &arg) {
  if (auto eq = arg.find('='); eq != std::string::npos && eq > 0)
    return {arg.substr(0, eq), arg.substr(eq + 1)};
  std::string stem = std::filesystem::path(arg).stem().string();
  if (stem.rfind("outfit_", 0) == 0 && stem.size() > 7)
    stem = stem.substr(7);
  return {stem, arg};
}

void addAnimOptions(CLI::App &app, AnimBakeOptions &anim) {
  app.add_option("--error-budget", anim.errorBudgetMm,
                 "largest error the player may show at any time, in mm at a 1.8 m character: "
                 "per clip the frame rate and for the pack the precision with the fewest bytes "
                 "that meet it (the report lists every option tried)")
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--fps",
         [&anim](const std::string &text) {
           try {
             anim.fps = AnimBakeOptions::parseFps(text);
           } catch (const Error &e) {
             throw CLI::ValidationError("--fps", e.what());
           }
         },
         "the texture's sampling rate, frames per second (forces it); \"source\": each clip's "
         "own key rate, so baked frames sit on the keys; \"auto\": the error budget picks from "
         "10 to 120 fps and the source rate. A rate other than auto selects the texture under "
         "--store auto; under --store tracks it sets the clip table's rate (the morph "
         "weights' frames)")
      ->default_str(AnimBakeOptions::fpsName(anim.fps));
  app.add_option("--precision", anim.precision,
                 "float (3 RGBA32F texels per joint), half (3 RGBA16F), qts (2 RGBA32F: "
                 "quaternion, translation, uniform scale) or qts-half (forces it, and selects "
                 "the texture under --store auto; an error with --store tracks); auto: the "
                 "error budget picks")
      ->capture_default_str();
  app.add_option("--max-width", anim.maxWidth, "texture width limit in texels")
      ->capture_default_str();
  app.add_option("--store", anim.store,
                 "the animation the pack stores: texture (joint matrices per frame, the ANIM "
                 "chunk); tracks (every clip compressed into joint tracks on its own keys "
                 "within the same error budget, the TRAK chunk: crowdplay decodes them on the "
                 "GPU; no texture is searched); both; auto: the fewer bytes among those meeting "
                 "the budget, the tracks first: where they meet it in fewer bytes than any "
                 "texture could take, no texture is searched; texture where --fps or "
                 "--precision shapes it (the report's store_reason says why)")
      ->check(CLI::IsMember(AnimBakeOptions::stores()))
      ->capture_default_str();
}

void addThreads(CLI::App &app, int &threads) {
  app.add_option("--threads", threads, "worker threads (0: all cores); output never depends on it")
      ->capture_default_str();
}

bool BakeArgs::progress() const { return !quiet && isatty(2); }

CharacterManifest BakeArgs::manifest() const {
  CharacterManifest m;
  m.name = std::filesystem::path(input).stem().string();
  m.body = input;
  m.input = files.policy;
  return m;
}

void BakeArgs::runJob(const CharacterManifest &m, const std::string &command,
                      const std::string &kind, int threads) const {
  ResourceGuard guard(files.limits, "crowdbake " + command + " " + input);
  const auto figures = runSingleJob(m, {command, kind, output, quiet, progress(), threads});
  if (!report.empty())
    writeJson(report, figures);
}

void printFailure(const std::exception &e) {
  std::string msg = e.what();
  for (char &ch : msg)
    if (ch == '\n')
      ch = ' ';
  const bool usage = dynamic_cast<const UsageError *>(&e) != nullptr;
  std::fprintf(stderr, "crowdbake: %s: %s\n", usage ? "usage" : "error", msg.c_str());
}

void writeJson(const std::string &path, const nlohmann::ordered_json &j) {
  const std::string text = j.dump(2) + "\n";
  pack::writeFileAtomic(path, {reinterpret_cast<const uint8_t *>(text.data()), text.size()});
}

const char *const kEveryMesh =
    "every skinned mesh with every skin it uses, merged into one skeleton, and the meshes "
    "rigidly parented to its joints";

} // namespace crowd::cli
