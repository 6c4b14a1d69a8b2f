#include "crowd/runtime/crowd_renderer.h"

#include <algorithm>
#include <cstring>

#include <epoxy/gl.h>
#include <glm/gtc/type_ptr.hpp>

#include "crowd/formats/error.h"
#include "crowd_shaders.h" // generated at build time from shaders/

namespace crowd::runtime {

namespace {

unsigned compile(GLenum type, const char *source, const char *name) {
  unsigned s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  int ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    throw Error(std::string("shader ") + name + " does not compile: " + log);
  }
  return s;
}

} // namespace

unsigned buildCrowdProgram() {
  unsigned vs = compile(GL_VERTEX_SHADER, kCrowdVert, "crowd.vert");
  unsigned fs = compile(GL_FRAGMENT_SHADER, kCrowdFrag, "crowd.frag");
  unsigned p = glCreateProgram();
  glAttachShader(p, vs);
  glAttachShader(p, fs);
  glLinkProgram(p);
  glDeleteShader(vs);
  glDeleteShader(fs);
  int ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetProgramInfoLog(p, sizeof log, nullptr, log);
    throw Error(std::string("shaders do not link: ") + log);
  }
  return p;
}

struct CrowdRenderer::Character {
  const pack::AnimationPack *pack = nullptr;
  unsigned vao = 0, buffers[7] = {}, textures[3] = {};
  std::vector<float> instanceData; // per instance: 3 rows + params, 16 floats
  uint32_t instanceCount = 0;

  ~Character() {
    glDeleteVertexArrays(1, &vao);
    glDeleteBuffers(7, buffers);
    glDeleteTextures(3, textures);
  }
};

CrowdRenderer::CrowdRenderer(const std::vector<pack::AnimationPack> &packs, const Scene &scene)
    : light_(scene.lightDirection) {
  program_ = buildCrowdProgram();
  for (size_t pi = 0; pi < packs.size(); ++pi) {
    const auto &p = packs[pi];
    characters_.push_back(std::make_unique<Character>());
    Character *c = characters_.back().get();
    c->pack = &p;
    // Clip of each scene clip name in this pack ("" = the first clip).
    std::vector<uint32_t> clipOf;
    for (const auto &name : scene.clipNames) {
      uint32_t found = name.empty() ? 0 : UINT32_MAX;
      for (uint32_t k = 0; k < p.clips.size() && found == UINT32_MAX; ++k)
        if (p.clips[k].name == name)
          found = k;
      if (found == UINT32_MAX) {
        std::string names;
        for (const auto &cl : p.clips)
          names += (names.empty() ? "" : ", ") + cl.name;
        throw Error(scene.path + ": clip '" + name + "' is not in pack '" + scene.packNames[pi] +
                    "' (clips: " + names + ")");
      }
      clipOf.push_back(found);
    }
    for (const auto &inst : scene.instances) {
      if (inst.pack != pi)
        continue;
      float cy = float(std::cos(inst.yaw)), sy = float(std::sin(inst.yaw));
      glm::vec3 t(inst.position);
      const float d[16] = {cy,
                           0,
                           sy,
                           t.x,
                           0,
                           1,
                           0,
                           t.y,
                           -sy,
                           0,
                           cy,
                           t.z,
                           float(clipOf[inst.clip]),
                           float(inst.timeOffset),
                           float(inst.speed),
                           float(inst.palette)};
      c->instanceData.insert(c->instanceData.end(), d, d + 16);
      ++c->instanceCount;
    }
    std::vector<float> clips;
    for (const auto &cl : p.clips)
      clips.insert(clips.end(),
                   {cl.fps, float(cl.frameCount), float(cl.firstFrame), cl.loop ? 1.0f : 0.0f});
    std::vector<float> colours;
    for (const auto &palette : scene.palettes)
      for (const auto &sub : p.mesh.subMeshes) {
        glm::vec3 col(0.8f);
        for (const auto &[region, value] : palette)
          if (region == "default")
            col = value;
        for (const auto &[region, value] : palette)
          if (region == sub.name)
            col = value;
        colours.insert(colours.end(), {col.r, col.g, col.b, 1.0f});
      }

    glCreateVertexArrays(1, &c->vao);
    glCreateBuffers(7, c->buffers);
    auto upload = [](unsigned b, const auto &v) {
      glNamedBufferStorage(b, GLsizeiptr(v.size() * sizeof(v[0])), v.data(), 0);
    };
    upload(c->buffers[0], p.mesh.positions);
    upload(c->buffers[1], p.mesh.normals);
    upload(c->buffers[2], p.mesh.indices);
    upload(c->buffers[3], clips);
    if (c->instanceData.empty())
      c->instanceData.assign(16, 0.0f);
    upload(c->buffers[4], c->instanceData);
    upload(c->buffers[5], colours);
    glVertexArrayVertexBuffer(c->vao, 0, c->buffers[0], 0, 12);
    glVertexArrayVertexBuffer(c->vao, 1, c->buffers[1], 0, 12);
    for (unsigned a = 0; a < 2; ++a) {
      glEnableVertexArrayAttrib(c->vao, a);
      glVertexArrayAttribFormat(c->vao, a, 3, GL_FLOAT, GL_FALSE, 0);
      glVertexArrayAttribBinding(c->vao, a, a);
    }
    if (!p.mesh.uvs.empty()) { // otherwise attribute 2 reads its default (0, 0)
      upload(c->buffers[6], p.mesh.uvs);
      glVertexArrayVertexBuffer(c->vao, 2, c->buffers[6], 0, 8);
      glEnableVertexArrayAttrib(c->vao, 2);
      glVertexArrayAttribFormat(c->vao, 2, 2, GL_FLOAT, GL_FALSE, 0);
      glVertexArrayAttribBinding(c->vao, 2, 2);
    }
    glVertexArrayElementBuffer(c->vao, c->buffers[2]);

    glCreateTextures(GL_TEXTURE_2D, 3, c->textures);
    const auto &t = p.animation;
    bool half = t.format == pack::TexelFormat::RGBA16F;
    glTextureStorage2D(c->textures[0], 1, half ? GL_RGBA16F : GL_RGBA32F, GLsizei(t.width),
                       GLsizei(t.height));
    glTextureSubImage2D(c->textures[0], 0, 0, 0, GLsizei(t.width), GLsizei(t.height), GL_RGBA,
                        half ? GL_HALF_FLOAT : GL_FLOAT, t.texels.data());
    glTextureStorage2D(c->textures[1], 1, GL_RGBA32F, GLsizei(p.skin.width),
                       GLsizei(p.skin.height));
    glTextureSubImage2D(c->textures[1], 0, 0, 0, GLsizei(p.skin.width), GLsizei(p.skin.height),
                        GL_RGBA, GL_FLOAT, p.skin.texels.data());
    for (unsigned tex : {c->textures[0], c->textures[1]}) {
      glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    if (p.diffuse) {
      const auto &d = *p.diffuse;
      int levels = 1;
      while ((std::max(d.width, d.height) >> levels) > 0)
        ++levels;
      glTextureStorage2D(c->textures[2], levels, GL_RGBA8, GLsizei(d.width), GLsizei(d.height));
      glTextureSubImage2D(c->textures[2], 0, 0, 0, GLsizei(d.width), GLsizei(d.height), GL_RGBA,
                          GL_UNSIGNED_BYTE, d.rgba.data());
      glGenerateTextureMipmap(c->textures[2]);
      glTextureParameteri(c->textures[2], GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
      glTextureParameteri(c->textures[2], GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    }
  }
}

CrowdRenderer::~CrowdRenderer() { glDeleteProgram(program_); }

DrawStats CrowdRenderer::draw(const glm::mat4 &viewProjection, float seconds, bool naive) {
  DrawStats stats;
  glUseProgram(program_);
  auto loc = [&](const char *name) { return glGetUniformLocation(program_, name); };
  glUniformMatrix4fv(loc("u_viewProjection"), 1, GL_FALSE, glm::value_ptr(viewProjection));
  glUniform1f(loc("u_time"), seconds);
  glUniform3fv(loc("u_lightDirection"), 1, glm::value_ptr(light_));
  glUniform1i(loc("u_naive"), naive);
  const int subMeshLoc = loc("u_subMesh"), rowsLoc = loc("u_rows"), paramsLoc = loc("u_params");
  for (const auto &c : characters_) {
    if (c->instanceCount == 0)
      continue;
    const auto &p = *c->pack;
    glUniform1i(loc("u_encoding"), int(p.animation.encoding));
    glUniform1i(loc("u_jointCount"), int(p.animation.jointCount));
    glUniform1i(loc("u_framesPerRow"), int(p.animation.framesPerRow));
    glUniform1i(loc("u_skinWidth"), int(p.skin.width));
    glUniform1i(loc("u_subMeshCount"), int(p.mesh.subMeshes.size()));
    glBindVertexArray(c->vao);
    glBindTextureUnit(0, c->textures[0]);
    glBindTextureUnit(1, c->textures[1]);
    glBindTextureUnit(2, c->textures[2]);
    glUniform1i(loc("u_hasTexture"), p.diffuse ? 1 : 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, c->buffers[3]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, c->buffers[4]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, c->buffers[5]);
    for (size_t s = 0; s < p.mesh.subMeshes.size(); ++s) {
      const auto &sub = p.mesh.subMeshes[s];
      glUniform1i(subMeshLoc, int(s));
      const void *offset = reinterpret_cast<const void *>(uintptr_t(sub.firstIndex) * 4);
      if (naive) {
        for (uint32_t i = 0; i < c->instanceCount; ++i) {
          glUniform4fv(rowsLoc, 3, &c->instanceData[size_t(i) * 16]);
          glUniform4fv(paramsLoc, 1, &c->instanceData[size_t(i) * 16 + 12]);
          glDrawElements(GL_TRIANGLES, GLsizei(sub.indexCount), GL_UNSIGNED_INT, offset);
          ++stats.drawCalls;
        }
      } else {
        glDrawElementsInstanced(GL_TRIANGLES, GLsizei(sub.indexCount), GL_UNSIGNED_INT, offset,
                                GLsizei(c->instanceCount));
        ++stats.drawCalls;
      }
      stats.triangles += uint64_t(sub.indexCount / 3) * c->instanceCount;
    }
    stats.instances += c->instanceCount;
  }
  return stats;
}

} // namespace crowd::runtime
