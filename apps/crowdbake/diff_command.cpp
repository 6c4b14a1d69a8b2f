// crowdbake diff: a new pack against a golden one, chunk by chunk, within tolerances
// (crowd/bake/pack_diff.h). Its exit code is the verdict, as idiff's is.
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "crowd/bake/input_files.h"
#include "crowd/bake/pack_diff.h"
#include "crowd/formats/error.h"
#include "crowd/support/json_checker.h"

namespace crowd::cli {

namespace {

const char *const kDiffHelp = R"(Compares NEW with GOLDEN chunk by chunk, in the units a user thinks
in, and exits with the verdict (like OpenImageIO's idiff):
  0  identical, or every change within its warn tolerance
  1  some change over its warn tolerance, none over its fail tolerance
  2  some change over its fail tolerance
  3  the packs hold different things: a chunk only in one, other joints, clips or vertex counts
  4  bad input or usage: a pack that cannot be read (truncated, damaged), a bad tolerances file
Animation: every vertex skinned with the player's math at every frame and mid-frame of both
packs, the largest displacement in mm at a 1.8 m character, naming the clip, time, vertex and
its joint. Skin: the same influences, the largest weight change. Mesh: positions (mm), normals
(degrees), UVs. LOD: the collapse error curve (relative), and whether the collapse order is the
same. Outfits and vertex sources: exact. Cloth loops: start, cycles and blend exact, positions
in mm (max and RMS). Impostor atlases and the diffuse texture: per channel in 0..1, absolute
(texel) and relative to the mean of the two values (texel_relative), with the percent of
texels past both fail tolerances allowed by texel_percent; region ids exact.
Provenance differences are listed, never failing. --tolerances FILE overrides any default:
{"animation_mm": {"warn": 0.01, "fail": 0.1}, "texel": {"fail": 0.02}, ...}; --report writes
every comparison, the tolerances used and the worst element as JSON.)";

// Prints one line per comparison that is not byte-identical, and a summary.
void print(const PackDiff &d, bool verbose) {
  size_t identical = 0;
  for (const auto &i : d.items) {
    identical += i.identical;
    if (i.identical && !verbose)
      continue;
    std::string value;
    if (!i.identical && !i.informational && i.verdict != DiffVerdict::Incomparable) {
      char b[64];
      std::snprintf(b, sizeof b, "%.4g%s%s", i.value, i.unit.empty() ? "" : " ", i.unit.c_str());
      value = std::string(": ") + b;
    }
    const char *verdict = i.identical ? "identical" : i.informational ? "listed" : name(i.verdict);
    const char *sep = i.worst.empty() ? "" : value.empty() ? ": " : ", ";
    std::printf("%-9s %-22s %s%s%s%s\n", verdict, i.chunk.c_str(), i.what.c_str(), value.c_str(),
                sep, i.worst.c_str());
  }
  std::printf("%s (%zu comparisons, %zu chunks byte-identical)\n", name(d.verdict), d.items.size(),
              identical);
}

} // namespace

int cmdDiff(int argc, char **argv) {
  std::string golden, fresh, tolerancesFile, report;
  bool verbose = false;
  try {
    CLI::App app(kDiffHelp, "crowdbake diff");
    example(app, "crowdbake diff golden/humanoid.crowdpack build/humanoid.crowdpack "
                 "--report diff.json");
    app.add_option("GOLDEN", golden, "the pack to compare against")->required();
    app.add_option("NEW", fresh, "the pack to check")->required();
    app.add_option("--tolerances", tolerancesFile, "JSON file of tolerances (see above)");
    app.add_option("--report", report, "write every comparison as JSON to FILE");
    app.add_flag("-v,--verbose", verbose, "list byte-identical chunks too");
    if (!parseArgs(app, argc, argv))
      return 0;
    DiffTolerances tolerances;
    if (!tolerancesFile.empty()) {
      const std::string text = readInputText(tolerancesFile, InputPolicy{});
      tolerances =
          tolerancesFromJson(support::JsonChecker(text, tolerancesFile).parse(), tolerancesFile);
    }
    const PackDiff d = diffPacks(pack::Reader::open(golden), pack::Reader::open(fresh), tolerances);
    print(d, verbose);
    if (!report.empty())
      writeJson(report, diffJson(d, tolerances));
    return int(d.verdict);
  } catch (const std::exception &e) {
    printFailure(e);
    return 4; // not compared
  }
}

} // namespace crowd::cli
