// One libFuzzer binary per target: SULCUS_FUZZ_TARGET names it.
#include <cstdio>
#include <cstdlib>

#include "tests/fuzz/targets.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const sulcus::fuzz::Target* target = [] {
    const sulcus::fuzz::Target* t = sulcus::fuzz::FindTarget(SULCUS_FUZZ_TARGET);
    if (!t) {
      std::fprintf(stderr, "no fuzz target %s\n", SULCUS_FUZZ_TARGET);
      std::abort();
    }
    return t;
  }();
  sulcus::fuzz::RunOne(*target, data, size);
  return 0;
}
