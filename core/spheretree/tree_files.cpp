#include "core/spheretree/tree_files.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/base/text.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

std::size_t FullSize(int levels, int branching) {
  std::size_t total = 0, per_level = 1;
  for (int l = 0; l < levels; ++l) {
    total += per_level;
    per_level *= branching;
  }
  return total;
}

constexpr char kMagic[8] = {'S', 'U', 'L', 'C', 'S', 'P', 'H', '\0'};
constexpr std::uint32_t kBinaryVersion = 1;

}  // namespace

std::uint64_t Fnv1a(const void* data, std::size_t size, std::uint64_t hash) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 0x100000001b3ull;
  }
  return hash;
}

void WriteSph(const SphereTree& tree, const fs::path& path) {
  tree.Validate();
  const std::size_t full = FullSize(tree.levels, tree.branching);
  // slot_of_node: breadth-first slots of the full array.
  std::vector<std::int64_t> node_in_slot(full, -1);
  std::vector<std::size_t> slot_of(tree.size(), 0);
  node_in_slot[0] = 0;
  for (std::size_t i = 0; i < tree.size(); ++i) {
    for (int c = 0; c < tree.child_count[i]; ++c) {
      const std::size_t slot = slot_of[i] * tree.branching + 1 + c;
      slot_of[tree.first_child[i] + c] = slot;
      node_in_slot[slot] = tree.first_child[i] + c;
    }
  }
  std::ofstream out(path);
  if (!out) throw TreeFileError(path.string() + ": cannot be opened for writing");
  out.precision(17);
  out << tree.levels << ' ' << tree.branching << '\n';
  for (std::size_t s = 0; s < full; ++s) {
    const std::int64_t n = node_in_slot[s];
    if (n < 0) {
      out << "0 0 0 -1 0\n";
    } else {
      out << tree.x[n] << ' ' << tree.y[n] << ' ' << tree.z[n] << ' ' << tree.r[n]
          << " 1\n";
    }
  }
  out.close();
  if (!out) throw TreeFileError(path.string() + ": write failed");
}

SphereTree ReadSph(const fs::path& path, const Vector3& offset) {
  const std::string name = path.string();
  std::ifstream in(path);
  if (!in) throw TreeFileError(name + ": cannot be opened (missing or unreadable)");
  std::string line;
  int line_no = 0;
  auto fail = [&](const std::string& what) -> void {
    throw TreeFileError(name + ":" + std::to_string(line_no) + ": " +
                        ShortenQuoted(what));
  };
  // First non-empty line: levels and branching.
  int levels = 0, branching = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream s(line);
    std::string extra;
    if (!(s >> levels >> branching) || (s >> extra)) {
      fail("expected 'levels branch' (two integers), found '" + line + "'");
    }
    break;
  }
  if (levels == 0) {
    line_no = std::max(line_no, 1);
    fail("empty file, expected 'levels branch' on the first line");
  }
  if (levels < 1 || levels > 10)
    fail("levels " + std::to_string(levels) + " out of range (1 to 10)");
  if (branching < 2 || branching > 32)
    fail("branch " + std::to_string(branching) + " out of range (2 to 32)");
  const std::size_t full = FullSize(levels, branching);
  if (full > 50'000'000) fail("tree too large");
  // Every node takes a line of at least four numbers ("0 0 0 0"): a header that
  // asks for more nodes than the file can hold is refused before anything is allocated.
  std::error_code size_ec;
  const std::uintmax_t bytes = fs::file_size(path, size_ec);
  if (!size_ec && full > bytes / 8 + 1)
    fail(std::to_string(levels) + " levels of " + std::to_string(branching) + " need " +
         std::to_string(full) + " node lines; a file of " + std::to_string(bytes) +
         " bytes cannot hold them");

  struct Slot {
    double x, y, z, r;
  };
  std::vector<Slot> slots;
  slots.reserve(full);
  while (slots.size() < full && std::getline(in, line)) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream s(line);
    std::vector<double> values;
    std::string token;
    while (s >> token) {
      char* end = nullptr;
      const double v = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0') fail("'" + token + "' is not a number");
      values.push_back(v);
    }
    if (values.size() != 4 && values.size() != 5 && values.size() != 10) {
      fail("expected 'x y z r occupancy' (4, 5 or 10 numbers), found " +
           std::to_string(values.size()));
    }
    for (double v : values) {
      if (!std::isfinite(v)) fail("non-finite number");
    }
    // Millimetres: a sphere 100 m across or 100 m away is no tooth's (and would overflow
    // what measures it).
    for (int k = 0; k < 4; ++k)
      if (std::abs(values[static_cast<std::size_t>(k)]) > 1e5)
        fail("'" + std::to_string(values[static_cast<std::size_t>(k)]) +
             "' mm is out of range (at most 100000 mm)");
    slots.push_back({values[0], values[1], values[2], values[3]});
  }
  if (slots.size() < full) {
    fail("file ends after " + std::to_string(slots.size()) + " of the " +
         std::to_string(full) + " node lines that " + std::to_string(levels) +
         " levels of " + std::to_string(branching) + " need");
  }
  if (!(slots[0].r > 0)) {
    line_no = 2;
    fail("the root sphere is unused (radius <= 0)");
  }
  // Breadth-first compaction of the used slots.
  SphereTree tree;
  tree.levels = levels;
  tree.branching = branching;
  std::vector<std::size_t> slot_of;
  tree.AddNode(Vector3(slots[0].x, slots[0].y, slots[0].z) + offset, slots[0].r, 0);
  slot_of.push_back(0);
  for (std::size_t i = 0; i < tree.size(); ++i) {
    if (tree.level[i] + 1 >= levels) continue;
    const std::size_t first_slot = slot_of[i] * branching + 1;
    tree.first_child[i] = static_cast<std::int32_t>(tree.size());
    for (int c = 0; c < branching; ++c) {
      const Slot& s = slots[first_slot + c];
      if (!(s.r > 0)) continue;
      tree.AddNode(Vector3(s.x, s.y, s.z) + offset, s.r, tree.level[i] + 1);
      slot_of.push_back(first_slot + c);
      ++tree.child_count[i];
    }
    if (tree.child_count[i] == 0) tree.first_child[i] = 0;
  }
  try {
    tree.Validate();
  } catch (const std::exception& e) {
    throw TreeFileError(name + ": " + e.what());
  }
  return tree;
}

void WriteTreeBinary(const SphereTree& tree, std::uint64_t key, const fs::path& path) {
  tree.Validate();
  std::string buf(kMagic, sizeof kMagic);
  auto put = [&](const void* p, std::size_t n) {
    buf.append(static_cast<const char*>(p), n);
  };
  const std::uint32_t header[4] = {kBinaryVersion,
                                   static_cast<std::uint32_t>(tree.levels),
                                   static_cast<std::uint32_t>(tree.branching),
                                   static_cast<std::uint32_t>(tree.size())};
  put(header, sizeof header);
  put(&key, sizeof key);
  for (const auto* v : {&tree.x, &tree.y, &tree.z, &tree.r})
    put(v->data(), v->size() * sizeof(double));
  put(tree.first_child.data(), tree.size() * sizeof(std::int32_t));
  put(tree.child_count.data(), tree.size());
  put(tree.level.data(), tree.size());
  const std::uint64_t checksum = Fnv1a(buf.data(), buf.size());
  put(&checksum, sizeof checksum);

  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw TreeFileError(tmp.string() + ": cannot be opened for writing");
    out.write(buf.data(), static_cast<std::streamsize>(buf.size()));
    out.close();
    if (!out) throw TreeFileError(tmp.string() + ": write failed");
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec)
    throw TreeFileError(path.string() + ": cannot be replaced (" + ec.message() + ")");
}

SphereTree ReadTreeBinary(const fs::path& path, std::uint64_t expected_key) {
  const std::string name = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw TreeFileError(name + ": cannot be opened");
  const std::string buf((std::istreambuf_iterator<char>(in)),
                        std::istreambuf_iterator<char>());
  constexpr std::size_t kHead =
      sizeof kMagic + 4 * sizeof(std::uint32_t) + sizeof(std::uint64_t);
  if (buf.size() < kHead + sizeof(std::uint64_t))
    throw TreeFileError(name + ": truncated (too short for a header)");
  if (std::memcmp(buf.data(), kMagic, sizeof kMagic) != 0)
    throw TreeFileError(name + ": not a Sulcus sphere-tree file");
  std::uint32_t header[4];
  std::memcpy(header, buf.data() + sizeof kMagic, sizeof header);
  if (header[0] != kBinaryVersion) {
    throw TreeFileError(name + ": format version " + std::to_string(header[0]) +
                        ", expected " + std::to_string(kBinaryVersion));
  }
  std::uint64_t key;
  std::memcpy(&key, buf.data() + sizeof kMagic + sizeof header, sizeof key);
  const std::size_t n = header[3];
  const std::size_t body = n * (4 * sizeof(double) + sizeof(std::int32_t) + 2);
  if (buf.size() != kHead + body + sizeof(std::uint64_t)) {
    throw TreeFileError(name + ": truncated or padded (" + std::to_string(buf.size()) +
                        " bytes, expected " + std::to_string(kHead + body + 8) + ")");
  }
  std::uint64_t stored;
  std::memcpy(&stored, buf.data() + kHead + body, sizeof stored);
  if (stored != Fnv1a(buf.data(), kHead + body))
    throw TreeFileError(name + ": checksum mismatch (corrupt)");
  if (key != expected_key)
    throw TreeFileError(name + ": built for another mesh or other parameters");
  if (n == 0)
    throw TreeFileError(name + ": holds no spheres (a tree has at least its root)");
  SphereTree tree;
  tree.levels = static_cast<int>(header[1]);
  tree.branching = static_cast<int>(header[2]);
  const char* p = buf.data() + kHead;
  for (auto* v : {&tree.x, &tree.y, &tree.z, &tree.r}) {
    v->resize(n);
    std::memcpy(v->data(), p, n * sizeof(double));
    p += n * sizeof(double);
  }
  tree.first_child.resize(n);
  std::memcpy(tree.first_child.data(), p, n * sizeof(std::int32_t));
  p += n * sizeof(std::int32_t);
  tree.child_count.assign(p, p + n);
  p += n;
  tree.level.assign(p, p + n);
  try {
    tree.Validate();
  } catch (const std::exception& e) {
    throw TreeFileError(name + ": " + e.what());
  }
  return tree;
}

}  // namespace sulcus
