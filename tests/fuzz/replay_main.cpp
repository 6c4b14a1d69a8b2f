// Replays inputs through a fuzz target's entry point without libFuzzer, so the committed corpus
// (tests/fuzz/corpus/TARGET) and every past finding's reproducer (tests/fuzz/regressions/TARGET)
// run as ctest fuzz_replay_TARGET in the release and sanitizer builds. Arguments: files, folders
// (every regular file in them) and DIR/PREFIX* (the files of DIR whose names start with PREFIX,
// maybe none). Replaying nothing is a failure: a missing folder must not pass as an empty one.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int main(int argc, char **argv) {
  namespace fs = std::filesystem;
  std::vector<fs::path> inputs;
  for (int i = 1; i < argc; ++i) {
    const fs::path arg = argv[i];
    const std::string text = argv[i];
    if (!text.empty() && text.back() == '*') {
      const fs::path dir = arg.parent_path();
      const std::string prefix = arg.filename().string();
      for (const auto &e : fs::directory_iterator(dir))
        if (e.is_regular_file() &&
            e.path().filename().string().rfind(prefix.substr(0, prefix.size() - 1), 0) == 0)
          inputs.push_back(e.path());
    } else if (fs::is_directory(arg)) {
      for (const auto &e : fs::directory_iterator(arg))
        if (e.is_regular_file() && e.path().filename().string()[0] != '.')
          inputs.push_back(e.path());
    } else if (fs::is_regular_file(arg)) {
      inputs.push_back(arg);
    } else {
      std::fprintf(stderr, "replay: %s: no such file or folder\n", argv[i]);
      return 1;
    }
  }
  std::sort(inputs.begin(), inputs.end());
  if (inputs.empty()) {
    std::fprintf(stderr, "replay: no inputs\n");
    return 1;
  }
  for (const auto &path : inputs) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    std::fprintf(stderr, "replay: %s (%zu bytes)\n", path.c_str(), bytes.size());
    LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
  }
  std::printf("replayed %zu inputs\n", inputs.size());
  return 0;
}
