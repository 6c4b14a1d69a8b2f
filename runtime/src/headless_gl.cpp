#include "crowd/runtime/headless_gl.h"

#include <algorithm>
#include <cstdio>
#include <vector>

#include <dlfcn.h>
#include <epoxy/egl.h>
#include <epoxy/gl.h>

namespace crowd::runtime {

namespace {

// A 4.5 core context on `display`, current and surfaceless, or EGL_NO_CONTEXT.
EGLContext coreContext(EGLDisplay display, std::string &why) {
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    why = "eglInitialize failed";
    return EGL_NO_CONTEXT;
  }
  if (!epoxy_has_egl_extension(display, "EGL_KHR_surfaceless_context")) {
    why = "no EGL_KHR_surfaceless_context";
    eglTerminate(display);
    return EGL_NO_CONTEXT;
  }
  // No surface is ever made; EGL's default asks for window configs, which a device has none of.
  const EGLint configAttributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_BIT, EGL_NONE};
  EGLConfig config;
  EGLint configs = 0;
  const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                      4,
                                      EGL_CONTEXT_MINOR_VERSION,
                                      5,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                      EGL_NONE};
  EGLContext context = EGL_NO_CONTEXT;
  if (eglBindAPI(EGL_OPENGL_API) &&
      eglChooseConfig(display, configAttributes, &config, 1, &configs) && configs == 1)
    context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttributes);
  if (context != EGL_NO_CONTEXT && eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context))
    return context;
  why = "no OpenGL 4.5 core context (EGL error 0x" + [] {
    char hex[16];
    std::snprintf(hex, sizeof hex, "%x", unsigned(eglGetError()));
    return std::string(hex);
  }() + ")";
  if (context != EGL_NO_CONTEXT)
    eglDestroyContext(display, context);
  eglTerminate(display);
  return EGL_NO_CONTEXT;
}

} // namespace

std::unique_ptr<HeadlessGl> HeadlessGl::open(std::string &why) {
  // libepoxy loads libEGL on the first call and aborts where it cannot: look first.
  void *egl = dlopen("libEGL.so.1", RTLD_LAZY);
  if (!egl) {
    why = std::string("no EGL library: ") + dlerror();
    return nullptr;
  }
  dlclose(egl);
  // NVIDIA's driver names the enumeration only within EGL_EXT_device_base.
  if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device") ||
      !(epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration") ||
        epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_base"))) {
    why = "EGL without EGL_EXT_platform_device and EGL_EXT_device_enumeration";
    return nullptr;
  }
  EGLint count = 0;
  eglQueryDevicesEXT(0, nullptr, &count);
  std::vector<EGLDeviceEXT> devices(size_t(std::max(count, 0)));
  if (devices.empty() || !eglQueryDevicesEXT(count, devices.data(), &count)) {
    why = "EGL lists no device";
    return nullptr;
  }
  std::string whys;
  for (EGLDeviceEXT device : devices) {
    EGLDisplay display = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
    std::string deviceWhy = "no display";
    if (display != EGL_NO_DISPLAY)
      if (EGLContext context = coreContext(display, deviceWhy); context != EGL_NO_CONTEXT) {
        if (epoxy_gl_version() >= 45)
          return std::unique_ptr<HeadlessGl>(new HeadlessGl(display, context));
        deviceWhy = "OpenGL " + std::to_string(epoxy_gl_version() / 10) + "." +
                    std::to_string(epoxy_gl_version() % 10) + " only";
        eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display, context);
        eglTerminate(display);
      }
    whys += (whys.empty() ? "" : "; ") + deviceWhy;
  }
  why = std::to_string(devices.size()) + " EGL device(s), none usable: " + whys;
  return nullptr;
}

HeadlessGl::~HeadlessGl() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
  eglTerminate(display_);
}

} // namespace crowd::runtime
