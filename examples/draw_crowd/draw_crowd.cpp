// Draws a crowd of one character pack with crowd::runtime into a framebuffer of its own, in an
// OpenGL 4.5 core context of its own (EGL, no window, no display), and writes the frame as a PNG:
// the calls an engine makes, in the order it makes them.
//
//   draw_crowd PACK OUT.png [INSTANCES]
#include <cmath>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <glm/gtc/matrix_transform.hpp>
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

#include "crowd/formats/character_pack.h"
#include "crowd/runtime/crowd_renderer.h"

namespace {

// 1. The engine's context: here the first EGL device that gives OpenGL 4.5 core, surfaceless.
void makeContext() {
  EGLDeviceEXT devices[8];
  EGLint count = 0;
  eglQueryDevicesEXT(8, devices, &count);
  for (EGLint d = 0; d < count; ++d) {
    EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devices[d], nullptr);
    const EGLint configAttributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                       EGL_OPENGL_BIT, EGL_NONE};
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLConfig config;
    EGLint configs = 0;
    if (display == EGL_NO_DISPLAY || !eglInitialize(display, nullptr, nullptr) ||
        !eglBindAPI(EGL_OPENGL_API) ||
        !eglChooseConfig(display, configAttributes, &config, 1, &configs) || configs != 1)
      continue;
    EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
    if (context != EGL_NO_CONTEXT &&
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
      return;
  }
  throw std::runtime_error("no EGL device offers an OpenGL 4.5 core context");
}

} // namespace

int main(int argc, char **argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: draw_crowd PACK OUT.png [INSTANCES]\n");
    return 2;
  }
  const int side = argc > 3 ? std::stoi(argv[3]) : 10; // a side x side square of instances
  const int width = 640, height = 360;
  try {
    makeContext();

    // 2. The pack, read and checked once (crowd::formats).
    const crowd::pack::CharacterPack pack =
        crowd::pack::loadCharacterPack(crowd::pack::Reader::open(argv[1]));
    const float radius = pack.body.mesh.boundingSphere[3];

    // 3. The crowd: where each instance stands, which clip it plays and from when.
    crowd::runtime::Scene scene;
    scene.packPaths = {argv[1]};
    scene.packNames = {"character"};
    scene.impostorPaths = {""};
    scene.clipNames = {pack.body.clips.at(0).name};
    scene.palettes = {{}}; // one palette: the pack's own colours
    const double spacing = 2.2 * radius;
    for (int z = 0; z < side; ++z)
      for (int x = 0; x < side; ++x) {
        crowd::runtime::Instance instance;
        instance.position = {(x - (side - 1) / 2.0) * spacing, 0, -z * spacing};
        instance.yaw = 0.3 * std::sin(x * 1.7 + z);
        instance.timeOffset = 0.37 * (x * side + z);
        scene.instances.push_back(instance);
      }

    // 4. The renderer uploads the pack and the instances (needs the current context).
    crowd::runtime::CrowdRenderer renderer({&pack.body}, {nullptr}, scene);

    // 5. The engine's framebuffer.
    GLuint fbo, colour, depth;
    glCreateFramebuffers(1, &fbo);
    glCreateRenderbuffers(1, &colour);
    glCreateRenderbuffers(1, &depth);
    glNamedRenderbufferStorage(colour, GL_RGBA8, width, height);
    glNamedRenderbufferStorage(depth, GL_DEPTH24_STENCIL8, width, height);
    glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour);
    glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, width, height);
    glEnable(GL_DEPTH_TEST);
    glClearColor(0.55f, 0.62f, 0.70f, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

    // 6. Each frame: the camera, then one call draws the crowd (culled, LOD, instanced).
    crowd::runtime::FrameView view;
    view.fovY = glm::radians(50.0);
    view.viewportHeight = height;
    const float extent = float(side * spacing); // the crowd's, from z = 0 back
    view.eye = glm::vec3(0, 0.35f * extent, 0.45f * extent);
    view.viewProjection =
        glm::perspective(float(view.fovY), float(width) / height, 0.01f * extent, 10 * extent) *
        glm::lookAt(view.eye, glm::vec3(0, 0, -0.4f * extent), glm::vec3(0, 1, 0));
    const crowd::runtime::DrawStats stats = renderer.draw(view, 1.0f, {});
    glFinish();

    std::vector<unsigned char> rgba(size_t(width) * height * 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    stbi_flip_vertically_on_write(1); // GL's rows run from the bottom
    if (!stbi_write_png(argv[2], width, height, 4, rgba.data(), width * 4))
      throw std::runtime_error(std::string("cannot write ") + argv[2]);
    size_t covered = 0; // pixels the crowd covers: not the clear colour (the top left corner's)
    const unsigned char *clear = &rgba[rgba.size() - size_t(width) * 4];
    for (size_t p = 0; p < rgba.size(); p += 4)
      covered += rgba[p] != clear[0] || rgba[p + 1] != clear[1] || rgba[p + 2] != clear[2];
    std::printf("%s: %u instances, %u visible, %u draw calls, %llu triangles, %zu of %d pixels "
                "covered\n",
                argv[2], stats.instances, stats.visible, stats.drawCalls,
                static_cast<unsigned long long>(stats.triangles), covered, width * height);
    return 0;
  } catch (const std::exception &e) {
    std::fprintf(stderr, "draw_crowd: %s\n", e.what());
    return 1;
  }
}
