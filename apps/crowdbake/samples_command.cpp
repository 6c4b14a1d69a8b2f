// crowdbake samples: the bundled sample characters, cloth caches and village.
#include <iostream>
#include <string>

#include "commands.h"
#include "crowd/samples/cloth_caches.h"
#include "crowd/samples/samples.h"

namespace crowd::cli {

namespace {

const char *const kSamplesHelp = R"(Writes humanoid.glb, outfit_dress.glb, outfit_jumper_skirt.glb
and outfit_shirt_trousers.glb into DIR, the environment village.glb (for crowdbake terrain) with its agents' images village_behaviour.png and village_callbacks.png, and the cloth caches of the dress's garment "dress" (PC2,
30 fps, every vertex in the glTF's order; simulated, about 5 s): skirt_walk.pc2 and
skirt_run.pc2 (a loose skirt over 40 walk or run cycles), skirt_stiff.pc2 (a stiff one that
settles, 8 walk cycles) and noise.pc2 (never repeats). The output is deterministic: the same
bytes on every run.)";

} // namespace

int cmdSamples(int argc, char **argv) {
  CLI::App app(kSamplesHelp, "crowdbake samples");
  example(app, "crowdbake samples --out samples_out");
  std::string out;
  bool noCloth = false;
  app.add_option("--out", out, "folder to write the samples into")->required();
  app.add_flag("--no-cloth", noCloth, "skip the cloth caches (the characters only)");
  if (!parseArgs(app, argc, argv))
    return 0;
  crowd::samples::writeSamples(out);
  for (const auto &f : crowd::samples::kFiles)
    std::cout << out << "/" << f << "\n";
  std::cout << out << "/" << crowd::samples::kVillageFile << "\n";
  if (!noCloth) {
    crowd::samples::writeClothCaches(out);
    for (const auto &f : crowd::samples::kCacheFiles)
      std::cout << out << "/" << f << "\n";
  }
  return 0;
}

} // namespace crowd::cli
