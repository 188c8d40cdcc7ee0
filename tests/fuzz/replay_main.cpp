// Replays inputs through a fuzz target without libFuzzer: the corpus and every
// input that ever failed, in every build (ctest). Usage: fuzz_replay TARGET PATH...
// (a folder stands for every file in it). Exit 0 when each was accepted or
// cleanly refused; a defect aborts.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/targets.h"

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s TARGET PATH...\n", argv[0]);
    return 2;
  }
  const sulcus::fuzz::Target* t = sulcus::fuzz::FindTarget(argv[1]);
  if (!t) {
    std::fprintf(stderr, "no fuzz target '%s'\n", argv[1]);
    return 2;
  }
  std::vector<fs::path> files;
  for (int i = 2; i < argc; ++i) {
    const fs::path p = argv[i];
    if (fs::is_directory(p)) {
      for (const auto& e : fs::directory_iterator(p))
        if (e.is_regular_file()) files.push_back(e.path());
    } else if (fs::exists(p)) {
      files.push_back(p);
    }
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    std::ifstream in(f, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)),
                            std::istreambuf_iterator<char>());
    std::fprintf(stderr, "%s: %s\n", t->name, f.filename().c_str());
    sulcus::fuzz::RunOne(*t, reinterpret_cast<const std::uint8_t*>(bytes.data()),
                         bytes.size());
  }
  std::printf("%s: %zu inputs, each accepted or cleanly refused\n", t->name,
              files.size());
  return files.empty() ? 1 : 0;
}
