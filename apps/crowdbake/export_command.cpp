// crowdbake export: a pack's images (every chunk's, through the chunk registry) and the
// character as a binary glTF other tools open (crowd/bake/gltf_export.h).
#include <filesystem>
#include <iostream>

#include "commands.h"
#include "crowd/bake/gltf_export.h"
#include "crowd/bake/pack_images.h"
#include "crowd/formats/character_pack.h"
#include "crowd/formats/error.h"
#include "crowd/formats/registry.h"
#include "crowd/support/images.h"

namespace crowd::cli {

namespace {

const char *const kExportHelp = R"(Writes what a pack holds in files other tools open.
--images: every image a chunk holds, through OpenImageIO: float textures as OpenEXR
(animation.exr, skin.exr), 8- and 16-bit ones as PNG (diffuse.png, per impostor and frame its
normals, UVs and regions); and, for a pack with a skeleton, preview.png: the mesh skinned a
quarter of the way into the first clip, seen from the front, one tint per sub-mesh.
--gltf: the character as the player draws it, as a binary glTF (Blender, three.js, an engine's
importer): an outfit's sub-meshes at a LOD cut with their materials and the diffuse texture,
the skeleton, 4 influences a vertex, and every clip as an animation of the poses the player
decodes (joint tracks: their own keys and interpolation; an animation texture: every frame),
morph targets with their weights. Cloth loops are not exported (a warning says so: their
garments move with their joints).)";

void writeImages(const pack::Reader &reader, const std::string &dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw Error(dir + ": cannot create directory: " + ec.message());
  for (const pack::Image &image : packImages(reader)) {
    const bool isFloat =
        image.pixel == pack::Image::Pixel::F16 || image.pixel == pack::Image::Pixel::F32;
    const std::string path = dir + "/" + image.name + (isFloat ? ".exr" : ".png");
    images::write(path, image);
    std::cout << path << "\n";
  }
}

} // namespace

int cmdExport(int argc, char **argv) {
  std::string path, dir, gltf;
  GltfExportOptions options;
  CLI::App app(kExportHelp, "crowdbake export");
  example(app, "crowdbake export humanoid.crowdpack --images textures/ --gltf humanoid.glb");
  app.add_option("PACK", path, "a .crowdpack file")->required();
  app.add_option("--images", dir, "folder to write the images into");
  app.add_option("--gltf", gltf, "the character as a binary glTF (.glb) file");
  app.add_option("--outfit", options.outfit, "--gltf: this outfit (default: the first)");
  app.add_option("--lod", options.lodVertices,
                 "--gltf: the LOD cut at this many vertices (default: full detail)");
  if (!parseArgs(app, argc, argv))
    return 0;
  if (dir.empty() && gltf.empty())
    throw UsageError("nothing to export: give --images DIR, --gltf OUT.glb or both");
  const auto reader = pack::Reader::open(path);
  if (!dir.empty())
    writeImages(reader, dir);
  if (!gltf.empty()) {
    if (!reader.find(pack::kSkeleton))
      throw Error("pack '" + path + "': --gltf needs a character pack (this one has no skeleton)");
    const pack::CharacterPack character = pack::loadCharacterPack(reader);
    Reporter reporter;
    if (!character.cloths.empty())
      reporter.warn("export_cloth", std::to_string(character.cloths.size()) +
                                        " cloth loops are not exported: their garments move "
                                        "with their joints only");
    pack::writeFileAtomic(gltf, exportGltf(character.body, options, reporter));
    std::cout << gltf << "\n";
  }
  return 0;
}

} // namespace crowd::cli
