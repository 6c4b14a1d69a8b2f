// Reads a crowdpack with crowd::formats alone and prints what it holds: its chunks and their
// sizes, then, for a character pack, its joints, clips, mesh, LOD, outfits, impostors and cloth
// loops. What an engine's asset importer does first; nothing here needs OpenGL or our tools.
//
//   read_pack PACK
#include <cstdio>
#include <exception>

#include "crowd/formats/character_pack.h"
#include "crowd/formats/container.h"
#include "crowd/formats/registry.h"
#include "crowd/formats/version.h"

int main(int argc, char **argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: read_pack PACK\n");
    return 2;
  }
  try {
    // Reader checks the header, the chunk table, every bound and every checksum up front.
    const crowd::pack::Reader reader = crowd::pack::Reader::open(argv[1]);
    std::printf("%s: crowdpack container %u, %zu bytes, %zu chunks (reader %s)\n", argv[1],
                reader.version(), reader.fileSize(), reader.chunks().size(), crowd::kVersion);
    for (const auto &chunk : reader.chunks()) {
      const auto *codec = crowd::pack::findCodec(chunk.type);
      std::printf("  %s v%u  %10llu bytes  %s\n", crowd::pack::fourccName(chunk.type).c_str(),
                  chunk.version, static_cast<unsigned long long>(chunk.size),
                  codec ? codec->title : "(unknown to this reader)");
    }
    if (!reader.find(crowd::pack::kSkeleton)) {
      std::printf("not a character pack (no skeleton): an impostor or terrain pack\n");
      return 0;
    }
    // Decodes every chunk and checks they agree (clips, outfits, impostors, cloth loops).
    const crowd::pack::CharacterPack pack = crowd::pack::loadCharacterPack(reader);
    const auto &body = pack.body;
    std::printf("joints: %zu\n", body.skeleton.jointCount());
    std::printf("clips: %zu\n", body.clips.size());
    for (const auto &clip : body.clips) {
      const double seconds = clip.frameCount > 1 ? (clip.frameCount - 1) / double(clip.fps) : 0;
      std::printf("  %-16s %5u frames at %5.1f fps  %6.2f s%s\n", clip.name.c_str(),
                  clip.frameCount, double(clip.fps), seconds, clip.loop ? "  loops" : "");
    }
    std::printf("animation: %s\n", body.hasTexture() ? "texture" : "joint tracks only");
    std::printf("mesh: %zu vertices, %zu triangles, %zu sub-meshes\n", body.mesh.vertexCount(),
                body.mesh.indices.size() / 3, body.mesh.subMeshes.size());
    if (body.lod)
      std::printf("lod: continuous, down to %u vertices\n", body.lod->floorVertices);
    if (body.outfits)
      for (const auto &outfit : body.outfits->outfits)
        std::printf("outfit: %-16s draws %zu sub-meshes\n", outfit.name.c_str(),
                    outfit.subMeshes.size());
    std::printf("impostors: %zu, cloth loops: %zu\n", pack.impostors.size(), pack.cloths.size());
    return 0;
  } catch (const std::exception &e) { // crowd::Error: what is wrong, and where in the file
    std::fprintf(stderr, "read_pack: %s\n", e.what());
    return 1;
  }
}
