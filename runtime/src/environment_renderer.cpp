#include "crowd/runtime/environment_renderer.h"

#include <epoxy/gl.h>
#include <glm/gtc/type_ptr.hpp>

#include "crowd/runtime/crowd_renderer.h"
#include "crowd_shaders.h"

namespace crowd::runtime {

EnvironmentRenderer::EnvironmentRenderer(const pack::Terrain &t) {
  program_ = buildProgram(kEnvironmentVert, kEnvironmentFrag, "environment");
  glCreateVertexArrays(1, &vao_);
  glCreateBuffers(4, buffers_);
  auto upload = [](unsigned buffer, const auto &v) {
    glNamedBufferStorage(buffer, GLsizeiptr(std::max<size_t>(v.size(), 1) * sizeof(v[0])),
                         v.empty() ? nullptr : v.data(), 0);
  };
  upload(buffers_[0], t.positions);
  upload(buffers_[1], t.normals);
  upload(buffers_[2], t.colours);
  upload(buffers_[3], t.indices);
  glVertexArrayVertexBuffer(vao_, 0, buffers_[0], 0, 12);
  glVertexArrayVertexBuffer(vao_, 1, buffers_[1], 0, 12);
  glVertexArrayVertexBuffer(vao_, 2, buffers_[2], 0, 4);
  glVertexArrayElementBuffer(vao_, buffers_[3]);
  const struct {
    GLuint index;
    GLint size;
    GLenum type;
    GLboolean normalized;
  } attributes[3] = {
      {0, 3, GL_FLOAT, GL_FALSE}, {1, 3, GL_FLOAT, GL_FALSE}, {2, 4, GL_UNSIGNED_BYTE, GL_TRUE}};
  for (const auto &a : attributes) {
    glEnableVertexArrayAttrib(vao_, a.index);
    glVertexArrayAttribFormat(vao_, a.index, a.size, a.type, a.normalized, 0);
    glVertexArrayAttribBinding(vao_, a.index, a.index);
  }
  indexCount_ = unsigned(t.indices.size());
  glCreateTextures(GL_TEXTURE_2D, 1, &shadowTexture_);
  glTextureStorage2D(shadowTexture_, 1, GL_R32F, GLsizei(t.width), GLsizei(t.depth));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(shadowTexture_, 0, 0, 0, GLsizei(t.width), GLsizei(t.depth), GL_RED, GL_FLOAT,
                      t.shadowHeights.data());
  grid_ = {t.originX, t.originZ, 1.0f / t.cell, 0};
}

EnvironmentRenderer::~EnvironmentRenderer() {
  glDeleteTextures(1, &shadowTexture_);
  glDeleteBuffers(4, buffers_);
  glDeleteVertexArrays(1, &vao_);
  glDeleteProgram(program_);
}

void EnvironmentRenderer::draw(const glm::mat4 &viewProjection,
                               const glm::vec3 &lightDirection) const {
  glUseProgram(program_);
  glUniformMatrix4fv(glGetUniformLocation(program_, "u_viewProjection"), 1, GL_FALSE,
                     glm::value_ptr(viewProjection));
  glUniform4fv(glGetUniformLocation(program_, "u_grid"), 1, glm::value_ptr(grid_));
  glUniform3fv(glGetUniformLocation(program_, "u_lightDirection"), 1,
               glm::value_ptr(lightDirection));
  glBindTextureUnit(0, shadowTexture_);
  glBindVertexArray(vao_);
  glDrawElements(GL_TRIANGLES, GLsizei(indexCount_), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

} // namespace crowd::runtime
