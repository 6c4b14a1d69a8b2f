// Where a material's base-colour texture takes its coordinates: which TEXCOORD_n set, and the
// KHR_texture_transform that maps them (gltfpack writes quantized UVs with one to dequantize
// them). The pack holds one set of UVs into one diffuse texture, so the importer reads that set
// and applies the transform to it.
#pragma once
#include <cmath>
#include <string>

#include <glm/glm.hpp>
#include <tiny_gltf.h>

namespace crowd::gltf {

struct BaseColourUv {
  int set = 0;
  glm::dmat3 transform{1.0}; // column-major: uv' = transform * (u, v, 1)
  bool identity = true;

  // A key that differs where two materials map one vertex's UVs differently.
  std::string key() const {
    std::string k = std::to_string(set);
    if (!identity)
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 2; ++r)
          k.append(",").append(std::to_string(transform[c][r])); // as vertexKeyOf's key
    return k;
  }
};

// The spec's matrix: translation(offset) * rotation * scale, with rotation's matrix
// (cos, sin; -sin, cos) by rows; the extension's texCoord overrides the texture info's.
inline BaseColourUv baseColourUv(const tinygltf::Model &model, int material) {
  BaseColourUv out;
  if (material < 0 || size_t(material) >= model.materials.size())
    return out;
  const tinygltf::TextureInfo &info =
      model.materials[size_t(material)].pbrMetallicRoughness.baseColorTexture;
  if (info.index < 0)
    return out;
  out.set = info.texCoord;
  const auto ext = info.extensions.find("KHR_texture_transform");
  if (ext == info.extensions.end() || !ext->second.IsObject())
    return out;
  const tinygltf::Value &t = ext->second;
  auto number = [](const tinygltf::Value &v, double fallback) {
    return v.IsNumber() || v.IsInt() ? v.GetNumberAsDouble() : fallback;
  };
  auto pair = [&](const char *name, glm::dvec2 fallback) {
    if (!t.Has(name) || !t.Get(name).IsArray() || t.Get(name).ArrayLen() != 2)
      return fallback;
    return glm::dvec2(number(t.Get(name).Get(0), fallback.x),
                      number(t.Get(name).Get(1), fallback.y));
  };
  const glm::dvec2 offset = pair("offset", glm::dvec2(0)), scale = pair("scale", glm::dvec2(1));
  const double rotation = t.Has("rotation") ? number(t.Get("rotation"), 0) : 0;
  if (t.Has("texCoord") && t.Get("texCoord").IsInt())
    out.set = t.Get("texCoord").GetNumberAsInt();
  const double c = std::cos(rotation), s = std::sin(rotation);
  const glm::dmat3 translate(1, 0, 0, 0, 1, 0, offset.x, offset.y, 1);
  const glm::dmat3 rotate(c, -s, 0, s, c, 0, 0, 0, 1); // columns: rows (c, s), (-s, c)
  const glm::dmat3 scaling(scale.x, 0, 0, 0, scale.y, 0, 0, 0, 1);
  out.transform = translate * rotate * scaling;
  out.identity = out.transform == glm::dmat3(1.0);
  return out;
}

} // namespace crowd::gltf
