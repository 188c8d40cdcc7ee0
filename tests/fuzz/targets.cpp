#include "tests/fuzz/targets.h"

#include <unistd.h>
#include <zstd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/geometry/mesh_io.h"
#include "core/haptics/recording.h"
#include "core/haptics/scripted_device.h"
#include "core/lesson/answers.h"
#include "core/lesson/lesson_spec.h"
#include "core/scene/scene.h"
#include "core/spheretree/tree_files.h"

namespace sulcus::fuzz {
namespace {

namespace fs = std::filesystem;

// One folder per process (fuzzers run jobs in parallel), in memory when it can be.
const fs::path& WorkDir() {
  static const fs::path dir = [] {
    const fs::path base =
        fs::exists("/dev/shm") ? fs::path("/dev/shm") : fs::temp_directory_path();
    fs::path d = base / ("sulcus-fuzz-" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

[[noreturn]] void Defect(const Target& t, const std::string& what) {
  std::fprintf(stderr, "fuzz target %s: DEFECT: %s\n", t.name, what.c_str());
  std::fflush(stderr);
  std::abort();
}

// A clean refusal names the file it refuses.
void CheckNamesFile(const Target& t, const fs::path& file, const std::string& message) {
  if (message.find(file.filename().string()) == std::string::npos)
    Defect(t, "the error does not name the file: " + message);
}

void Read(const Target& t, const fs::path& file) {
  const std::string n = t.name;
  if (n == "scene") {
    LoadSceneSpec(file);
  } else if (n == "lesson") {
    LoadLessonSpec(file);
  } else if (n == "answers") {
    LoadAnswers(file);
  } else if (n.rfind("mesh_", 0) == 0) {
    LoadMesh(file);
  } else if (n == "sph") {
    ReadSph(file);
  } else if (n == "tree_cache") {
    // The cache is checksummed: take the key from the file and fix the checksum
    // up, so that the fuzzer reaches the structure behind it.
    std::ifstream in(file, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)),
                      std::istreambuf_iterator<char>());
    std::uint64_t key = 0;
    constexpr std::size_t kKeyAt = 8 + 16;
    if (bytes.size() >= kKeyAt + 8 + 8) {
      std::memcpy(&key, bytes.data() + kKeyAt, 8);
      const std::uint64_t sum = Fnv1a(bytes.data(), bytes.size() - 8);
      std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
      std::ofstream(file, std::ios::binary | std::ios::trunc)
          .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    ReadTreeBinary(file, key);
  } else if (n == "recording") {
    ReadRecording(file);
  } else if (n == "recording_ticks") {
    // The input is the decompressed tick stream of format 3: put a header before
    // it and compress it, so that the fuzzer works on the tick decoder itself.
    std::ifstream in(file, std::ios::binary);
    const std::string ticks((std::istreambuf_iterator<char>(in)),
                            std::istreambuf_iterator<char>());
    std::string packed(ZSTD_compressBound(ticks.size()), '\0');
    const std::size_t n_packed =
        ZSTD_compress(packed.data(), packed.size(), ticks.data(), ticks.size(), 1);
    if (ZSTD_isError(n_packed)) Defect(t, "zstd cannot compress the input");
    std::string bytes("SULCUSR\n");
    const auto put = [&](const auto& v) {
      bytes.append(reinterpret_cast<const char*>(&v), sizeof(v));
    };
    put(kRecordingVersion);
    put(std::uint64_t{0});
    put(1000.0);
    put(std::uint32_t{0});
    put(std::uint32_t{0});
    bytes.append(packed.data(), n_packed);
    std::ofstream(file, std::ios::binary | std::ios::trunc)
        .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    ReadRecording(file);
  } else if (n == "trajectory_csv") {
    LoadTrajectoryCsv(file);
  } else {
    Defect(t, "unknown target");
  }
}

}  // namespace

const std::vector<Target>& Targets() {
  static const std::vector<Target> targets = {
      {"scene", ".yaml"},         {"lesson", ".yaml"},
      {"answers", ".yaml"},       {"mesh_stl", ".stl"},
      {"mesh_obj", ".obj"},       {"mesh_ply", ".ply"},
      {"mesh_off", ".off"},       {"sph", ".sph"},
      {"tree_cache", ".bin"},     {"recording", ".rec"},
      {"trajectory_csv", ".csv"}, {"recording_ticks", ".ticks"},
  };
  return targets;
}

const Target* FindTarget(const std::string& name) {
  for (const Target& t : Targets())
    if (name == t.name) return &t;
  return nullptr;
}

// Lessons name their scene relative to their folder (`../scenes/...`): the
// shipped scenes are copied beside the lesson's folder once.
fs::path LessonDir() {
  static const fs::path dir = [] {
    const fs::path lessons = WorkDir() / "lessons", scenes = WorkDir() / "scenes";
    fs::create_directories(lessons);
    fs::create_directories(scenes);
    for (const auto& e : fs::directory_iterator(fs::path(SULCUS_SOURCE_DIR) / "scenes"))
      if (e.path().extension() == ".yaml")
        fs::copy_file(e.path(), scenes / e.path().filename(),
                      fs::copy_options::overwrite_existing);
    return lessons;
  }();
  return dir;
}

void RunOne(const Target& t, const std::uint8_t* data, std::size_t size) {
  const fs::path dir = std::string(t.name) == "lesson" ? LessonDir() : WorkDir();
  const fs::path file = dir / (std::string("input") + t.extension);
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    Read(t, file);
  } catch (const LoadError& e) {
    for (const ErrorAt& err : e.errors())
      if (err.file.empty()) Defect(t, "an error without its file: " + err.message);
    CheckNamesFile(t, file, e.what());
  } catch (const MeshError& e) {
    CheckNamesFile(t, file, e.what());
  } catch (const TreeFileError& e) {
    CheckNamesFile(t, file, e.what());
  } catch (const RecordingError& e) {
    CheckNamesFile(t, file, e.what());
  } catch (const std::invalid_argument& e) {
    CheckNamesFile(t, file, e.what());  // the trajectory reader's
  } catch (const std::runtime_error& e) {
    // Our readers' runtime errors name their file; a library's (filesystem,
    // yaml-cpp, std::) would not.
    CheckNamesFile(t, file, e.what());
  } catch (const std::exception& e) {
    Defect(t, std::string("a library's exception reached the user: ") + e.what());
  }
}

}  // namespace sulcus::fuzz
