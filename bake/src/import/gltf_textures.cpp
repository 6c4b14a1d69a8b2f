#include "importer.h"

#include <algorithm>

#include "crowd/formats/limits.h"
#include "crowd/support/images.h"

namespace crowd::gltf {

// The base-colour image of a material (EXT_texture_webp's where it names one), or -1.
int Importer::baseColorImage(int material) const {
  if (material < 0 || size_t(material) >= model_.materials.size())
    return -1;
  int texture = model_.materials[size_t(material)].pbrMetallicRoughness.baseColorTexture.index;
  if (texture < 0 || size_t(texture) >= model_.textures.size())
    return -1;
  // EXT_texture_webp names its WebP image apart (`source` is then an optional fallback, or
  // absent): the WebP one, which the decoder reads like any other.
  const auto &t = model_.textures[size_t(texture)];
  int image = t.source;
  if (const auto webp = t.extensions.find("EXT_texture_webp"); webp != t.extensions.end())
    if (webp->second.Has("source") && webp->second.Get("source").IsNumber())
      image = webp->second.Get("source").GetNumberAsInt();
  return image >= 0 && size_t(image) < model_.images.size() ? image : -1;
}

// The base-colour image covering the most triangles becomes the pack's diffuse texture.
void Importer::readDiffuseTexture() {
  if (trianglesPerImage_.empty())
    return;
  auto best = std::max_element(trianglesPerImage_.begin(), trianglesPerImage_.end(),
                               [](auto &a, auto &b) { return a.second < b.second; });
  int image = best->first;
  if (trianglesPerImage_.size() > 1)
    reporter_.warn("several_diffuse_textures",
                   std::to_string(trianglesPerImage_.size()) +
                       " base-colour textures: a pack holds one, kept image " +
                       std::to_string(image) + " (the one covering most triangles)",
                   trianglesPerImage_.size());
  auto warn = [&](const std::string &why) {
    reporter_.warn("diffuse_texture_skipped", "image " + std::to_string(image) + ": " + why +
                                                  ": baked without a diffuse texture");
  };
  stage_ = "decoding image " + std::to_string(image);
  auto it = encodedImages_.find(image);
  if (it == encodedImages_.end())
    return warn("no image data");
  const std::string &mime = model_.images[size_t(image)].mimeType;
  const std::string name = mime == "image/jpeg"   ? "image.jpg"
                           : mime == "image/webp" ? "image.webp"
                                                  : "image.png";
  pack::Image decoded;
  std::string why;
  if (!images::decode(it->second, name, limits::kImageSide, decoded, why))
    return warn(why);
  const std::vector<uint8_t> &pixels = decoded.bytes;
  DiffuseTexture t{int(decoded.width), int(decoded.height), {}};
  t.rgba.resize(size_t(t.width) * size_t(t.height) * 4);
  for (size_t p = 0; p < size_t(t.width) * size_t(t.height); ++p)
    for (size_t k = 0; k < 4; ++k) {
      size_t c = size_t(decoded.channels);
      // Grey, grey+alpha, RGB and RGBA sources all become RGBA.
      uint8_t v = k < 3 ? pixels[p * c + (c >= 3 ? k : 0)]
                        : (c == 2 || c == 4 ? pixels[p * c + c - 1] : 255);
      t.rgba[p * 4 + k] = v;
    }
  out_.diffuse = std::move(t);
}

} // namespace crowd::gltf
