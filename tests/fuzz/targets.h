#pragma once
// Every file Sulcus reads, as a fuzz target: the bytes are written to a file of
// the format's extension and handed to the reader. A reader may accept the file
// or refuse it with its own error that names the file; anything else (a crash,
// a sanitizer report, another exception, an error that does not name the file)
// is a defect and aborts. Used by the libFuzzer binaries (fuzz_main.cpp) and by
// the plain replay of the corpus and of every input that ever failed (ctest).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sulcus::fuzz {

struct Target {
  const char* name;       // scene, lesson, answers, mesh_stl, ...
  const char* extension;  // the file's, which picks the reader for meshes
};

const std::vector<Target>& Targets();
const Target* FindTarget(const std::string& name);

/// Reads the bytes as the target's file. Returns normally when the reader
/// accepted or cleanly refused them; aborts (with the reason on stderr) otherwise.
void RunOne(const Target& target, const std::uint8_t* data, std::size_t size);

}  // namespace sulcus::fuzz
