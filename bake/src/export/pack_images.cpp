#include "crowd/bake/pack_images.h"

#include "crowd/bake/preview.h"
#include "crowd/formats/chunks.h"

namespace crowd {

std::vector<pack::Image> packImages(const pack::Reader &reader) {
  std::vector<pack::Image> out;
  for (size_t i = 0; i < reader.chunks().size(); ++i) {
    const auto &c = reader.chunks()[i];
    const std::string ctx = pack::chunkContext(reader, i);
    const pack::ChunkCodec &codec = pack::codecOf(c, ctx);
    if (!codec.images)
      continue;
    for (auto &image : codec.images(reader.payload(c), c.version, ctx))
      out.push_back(std::move(image));
  }
  if (reader.find(pack::kSkeleton)) {
    const auto p = pack::loadAnimationPack(reader);
    const uint32_t size = 512;
    const uint32_t frame = p.clips.empty() ? 0 : p.clips[0].frameCount / 4;
    out.push_back(
        {"preview", size, size, 3, pack::Image::Pixel::U8, renderPreview(p, 0, frame, int(size))});
  }
  return out;
}

} // namespace crowd
