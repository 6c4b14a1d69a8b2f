// Fuzzes the player's scene reader (crowdplay's SCENE.json): any text must parse or give a
// crowd::Error, never a crash, UB, a hang or an allocation past the reader's checked limits.
#include <cstdint>
#include <string>

#include "crowd/formats/error.h"
#include "crowd/runtime/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const std::string text(reinterpret_cast<const char *>(data), size);
  try {
    (void)crowd::runtime::parseScene(text, "/nonexistent/fuzz/scene.json");
  } catch (const crowd::Error &) {
  }
  return 0;
}
