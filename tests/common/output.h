#pragma once
// Where a test writes its files: SULCUS_TEST_OUTPUT/<folder>/<name> in the build
// tree (the folder is created). SULCUS_TEST_OUTPUT is defined per test target.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace sulcus::test {

inline std::filesystem::path OutputPath(const std::string& folder,
                                        const std::string& name = "") {
  const std::filesystem::path dir = std::filesystem::path(SULCUS_TEST_OUTPUT) / folder;
  std::filesystem::create_directories(dir);
  return name.empty() ? dir : dir / name;
}

/// The same folder's subfolder `name`, emptied: a test that starts from nothing.
inline std::filesystem::path FreshOutputPath(const std::string& folder,
                                             const std::string& name) {
  const std::filesystem::path dir = OutputPath(folder, name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Writes `text` to `file` (replacing it) and returns the path.
inline std::filesystem::path WriteText(const std::filesystem::path& file,
                                       const std::string& text) {
  std::ofstream(file) << text;
  return file;
}

/// The whole of `file` (empty when it cannot be read): a log shown in a failure.
inline std::string ReadText(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in),
                     std::istreambuf_iterator<char>());
}

}  // namespace sulcus::test
