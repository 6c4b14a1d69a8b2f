#pragma once
// An OpenGL 4.5 core context with no window and no display, through EGL: on a GPU machine with
// no X server (the device's driver), or on Mesa's software device. The player's --headless mode
// and the GPU tests draw into their own framebuffers, so they need no surface at all.
#include <memory>
#include <string>

namespace crowd::runtime {

class HeadlessGl {
public:
  // Makes the context current on this thread, or returns null with `why` set: no EGL library,
  // no device, or no device offering OpenGL 4.5 core. Devices are tried in EGL's order.
  static std::unique_ptr<HeadlessGl> open(std::string &why);
  ~HeadlessGl();
  HeadlessGl(const HeadlessGl &) = delete;
  HeadlessGl &operator=(const HeadlessGl &) = delete;

private:
  HeadlessGl(void *display, void *context) : display_(display), context_(context) {}
  void *display_, *context_;
};

} // namespace crowd::runtime
