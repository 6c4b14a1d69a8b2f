// crowdbake cloth: a long cloth cache of one garment into a loop in phase with a body clip.
#include <filesystem>

#include "args.h"
#include "commands.h"
#include "crowd/bake/cloth_bake.h"

namespace crowd::cli {

namespace {

const char *const kClothDescription =
    R"(A loose garment pre-simulated over a body clip repeated many
times does not settle into an exact period; this bake finds the best loop in the cache. The
cache (PC2 or MDD: the garment's vertices, in the outfit glTF's order, every frame) is checked
against the garment (vertex count, then frame 0 against the garment at the clip's start) and read
in the body's root frame. Pass 1 compares the two ends of every loop of whole clip cycles (every
start frame) by squared vertex distances plus velocity differences, filtered along the
diagonal; the best --candidates go to pass 2, which renders the garment at both ends from
--views cameras, takes Canny edge images (OpenCV) and compares them by a symmetric mean edge
distance; the smallest wins. A seam that still jumps more than the cloth's mean per-frame
motion, or is no better than a typical seam, is cross-faded over --blend frames, and vertices
the blend moved into the body are pushed back out. The loop is stored as 16-bit positions in
the body's root frame (a CLTH chunk); the report gives every candidate's scores, the verdict,
the blend, the push-out and the quantisation error in mm at a 1.8 m character. In a character
manifest: "cloth": [{"outfit", "garment", "clip", "cache"}].)";

} // namespace

int cmdCloth(int argc, char **argv) {
  CLI::App app(kClothDescription, "crowdbake cloth");
  example(app, "crowdbake cloth skirt_walk.pc2 --body humanoid.glb --outfit outfit_dress.glb "
               "--garment dress --clip walk --fps 30 -o dress_walk.crowdpack --report r.json");
  BakeArgs b;
  b.add(app, "the cloth cache (.pc2 or .mdd)");
  ClothEntry e;
  std::string body, outfitFile;
  ClothBakeOptions &o = e.options;
  int threads = 0;
  app.add_option("--body", body, "the body glTF the garment was simulated on")->required();
  app.add_option("--outfit", outfitFile,
                 "[NAME=]FILE: the outfit glTF holding the garment; its name defaults to the "
                 "file name without extension and without an \"outfit_\" prefix")
      ->required();
  app.add_option("--garment", e.garment, "the garment: the outfit's material name")->required();
  app.add_option("--clip", e.clip, "the body clip the cache repeats")->required();
  app.add_option("--fps", o.cache.fps, "the cache's frame rate (PC2 stores none; 0: the file's)")
      ->capture_default_str();
  app.add_option("--candidates", o.loop.search.candidates, "loops pass 1 keeps for pass 2")
      ->capture_default_str();
  app.add_option("--views", o.loop.edges.views, "pass 2's cameras around the garment")
      ->capture_default_str();
  app.add_option("--min-cycles", o.loop.search.minCycles, "the shortest loop, in clip cycles")
      ->capture_default_str();
  app.add_option("--max-cycles", o.loop.search.maxCycles,
                 "the longest loop, in clip cycles: caps the loop's bytes, which grow with its "
                 "length (0: as long as the cache allows)")
      ->capture_default_str();
  app.add_option("--blend", o.blend,
                 "cross-fade frames when the seam is not acceptable (-1: as many as the verdict "
                 "names; 0: a hard cut always)")
      ->capture_default_str();
  app.add_option("--max-jump", o.loop.maxJumpRatio,
                 "a hard cut may jump at most this many times the mean per-frame motion (and "
                 "velocity change)")
      ->capture_default_str();
  addThreads(app, threads);
  if (!parseArgs(app, argc, argv))
    return 0;
  b.files.finish();
  validated(o);
  CharacterManifest m = b.manifest();
  m.body = body;
  m.name = std::filesystem::path(b.input).stem().string();
  const auto [outfitName, file] = outfitNameAndFile(outfitFile);
  e.outfit = outfitName;
  e.cache = b.input;
  m.outfits.emplace_back(outfitName, file);
  m.cloth.push_back(e);
  m.lod = false;
  b.runJob(m, "cloth", "cloth", threads);
  return 0;
}

} // namespace crowd::cli
