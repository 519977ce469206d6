// One libFuzzer binary per target: MDBRIEF_FUZZ_TARGET names it at compile time.
#include <cstring>

#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const auto* target = [] {
    for (const auto& t : mdbrief::fuzz::targets())
      if (std::strcmp(t.name, MDBRIEF_FUZZ_TARGET) == 0) return &t;
    __builtin_trap();
  }();
  target->run(data, size);
  return 0;
}
