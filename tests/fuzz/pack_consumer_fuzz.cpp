// Fuzzes what consumers do with a pack the reader accepts (a pack that verified once crashed
// export and the player): the player's CPU-side preparation (joint texel and morph slot words,
// cloth buffers, LOD ladders and their index data, render queues, impostor mips and spans, joint
// track words and palettes, no GL), crowdbake pose at a few times, and the images export writes.
// Any bytes must give results or a crowd::Error, never a crash or UB. Each input is read as it
// is and with its checksums repaired (pack_reader_fuzz's repair), so mutations reach the chunks.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "crowd/formats/character_pack.h"
#include "crowd/formats/chunks.h"
#include "crowd/formats/error.h"
#include "crowd/formats/impostor.h"
#include "crowd/formats/impostor_spans.h"
#include "crowd/formats/registry.h"
#include "crowd/runtime/cloth_playback.h"
#include "crowd/runtime/impostor_runtime.h"
#include "crowd/runtime/lod_select.h"
#include "crowd/runtime/pose.h"
#include "crowd/runtime/render_queues.h"
#include "crowd/runtime/texture_skinning.h"
#include "crowd/runtime/track_palettes.h"
#include "pack_repair.h"

using namespace crowd;

namespace {

// What crowd_renderer.cpp's constructor prepares for an impostor, without the upload.
void prepareImpostor(const pack::Impostor &m) {
  const uint32_t levels = runtime::impostorMipLevels(m);
  const size_t perFrame = m.views.size() / m.frames;
  for (uint32_t f = 0; f < m.frames; ++f) {
    const auto views = std::span(m.views).subspan(f * perFrame, perFrame);
    const auto mips = runtime::impostorMips(m, f, levels);
    for (uint32_t l = 0; l < mips.size(); ++l)
      pack::impostorSpans(views, mips[l].regions, mips[l].width, mips[l].height, l);
  }
}

void consume(std::vector<uint8_t> bytes) {
  try {
    const pack::Reader r(std::move(bytes), "fuzz");
    for (size_t i = 0; i < r.chunks().size(); ++i) { // export's images
      const pack::ChunkEntry &c = r.chunks()[i];
      const pack::ChunkCodec &codec = pack::codecOf(c, pack::chunkContext(r, i));
      if (codec.images)
        codec.images(r.payload(c), c.version, "fuzz");
    }
    if (r.find(pack::kImpostor) && !r.find(pack::kSkeleton)) {
      prepareImpostor(pack::loadImpostorPack(r).impostor);
      return;
    }
    const pack::CharacterPack character = pack::loadCharacterPack(r);
    const pack::AnimationPack &p = character.body;
    runtime::jointTexelWords(p.animation);
    runtime::morphSlotWords(p.morphs ? &*p.morphs : nullptr);
    runtime::clothBuffers(p, character.cloths);
    const runtime::LodLevels ladder = runtime::lodLevels(p);
    std::vector<uint32_t> starts;
    for (size_t k = 0; k < ladder.vertices.size(); k += 1 + ladder.vertices.size() / 4)
      runtime::lodIndices(p, ladder.vertices[k], starts);
    for (bool wholeBody : {false, true})
      runtime::RenderQueues(runtime::outfitSubMeshes(p, wholeBody),
                            uint32_t(p.mesh.subMeshes.size()));
    for (const auto &m : character.impostors)
      prepareImpostor(m);
    if (p.tracks) {
      runtime::trackWords(p);
      for (float seconds : {0.0f, 0.37f, 1e4f})
        runtime::decodePalette(p, runtime::paletteRequest(p, {0, 0, 1, 0}, {-1, 0, 0, 0}, seconds));
    }
    // crowdbake pose: the first clip and outfit at full detail, at three times.
    const runtime::PoseMesh mesh = runtime::poseMesh(p, {}, character.cloths);
    std::vector<glm::vec3> positions, normals;
    for (float seconds : {0.0f, 0.41f, 1e4f})
      runtime::poseAt(p, mesh, seconds, positions, normals);
  } catch (const Error &) {
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);
  consume(bytes);
  consume(fuzz::repaired(std::move(bytes)));
  return 0;
}
