#include "core/spheretree/tree_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/geometry/primitives.h"
#include "core/spheretree/builder.h"
#include "tests/common/output.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Out(const std::string& name) { return test::OutputPath("tree_files", name); }

void Write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

void ExpectSame(const SphereTree& a, const SphereTree& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.levels, b.levels);
  EXPECT_EQ(a.branching, b.branching);
  EXPECT_EQ(a.x, b.x);  // 17 significant digits: exact
  EXPECT_EQ(a.y, b.y);
  EXPECT_EQ(a.z, b.z);
  EXPECT_EQ(a.r, b.r);
  EXPECT_EQ(a.first_child, b.first_child);
  EXPECT_EQ(a.child_count, b.child_count);
  EXPECT_EQ(a.level, b.level);
}

const SphereTree& BuiltTree() {
  static const SphereTree tree = [] {
    SphereTreeParams p;
    p.levels = 3;
    p.leaves = 40;
    p.samples = 2000;
    return BuildSphereTree(MakeTorus(10, 3, 32, 16), p);
  }();
  return tree;
}

TEST(SphFormat, RoundTripIsExactAndFullArray) {
  const SphereTree& tree = BuiltTree();
  WriteSph(tree, Out("torus.sph"));
  std::ifstream in(Out("torus.sph"));
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, "3 8");
  int lines = 0, unused = 0;
  for (std::string line; std::getline(in, line);) {
    ++lines;
    std::istringstream s(line);
    double x, y, z, r, occupancy;
    ASSERT_TRUE(s >> x >> y >> z >> r >> occupancy) << line;
    unused += r < 0;
  }
  EXPECT_EQ(lines, 1 + 8 + 64);  // the full 8-ary array of 3 levels
  EXPECT_EQ(lines - unused, static_cast<int>(tree.size()));
  ExpectSame(ReadSph(Out("torus.sph")), tree);
}

TEST(SphFormat, ReadsBradshawStyleFiles) {
  // Two levels of branch 2: root, then two slots; the second unused. Six
  // decimals as his toolkit prints, and the 10-number form with an auxiliary sphere.
  Write(Out("bradshaw.sph"),
        "2 2\n"
        "0.000000 0.000000 0.000000 2.500000 1.000000\n"
        "1.000000 0.000000 0.000000 1.000000 1.000000 1.1 0 0 1 0.5\n"
        "0.000000 0.000000 0.000000 -1.000000 1.000000\n");
  const SphereTree t = ReadSph(Out("bradshaw.sph"), Vector3(10, 0, 0));
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t.child_count[0], 1);
  EXPECT_DOUBLE_EQ(t.x[1], 11.0);  // the offset moves recentred files back
  EXPECT_DOUBLE_EQ(t.r[0], 2.5);
}

void ExpectReadFails(const std::string& text, const std::string& message) {
  const fs::path p = Out("bad.sph");
  Write(p, text);
  try {
    ReadSph(p);
    ADD_FAILURE() << "accepted, expected: " << message;
  } catch (const TreeFileError& e) {
    EXPECT_EQ(std::string(e.what()), p.string() + message);
  }
}

TEST(SphFormat, CorruptFilesNameFileAndLine) {
  ExpectReadFails("", ":1: empty file, expected 'levels branch' on the first line");
  ExpectReadFails("4\n", ":1: expected 'levels branch' (two integers), found '4'");
  ExpectReadFails("2 1\n", ":1: branch 1 out of range (2 to 32)");
  ExpectReadFails("2 2\n0 0 0 1 1\n0 0 zero 1 1\n", ":3: 'zero' is not a number");
  ExpectReadFails("2 2\n0 0 0 1 1\n0 0 1 1 1 1\n",
                  ":3: expected 'x y z r occupancy' (4, 5 or 10 numbers), found 6");
  ExpectReadFails("2 2\n0 0 0 1 1\n0 0 0 nan 1\n", ":3: non-finite number");
  ExpectReadFails("2 2\n0 0 0 1 1\n0 0 0 1 1\n",
                  ":3: file ends after 2 of the 3 node lines that 2 levels of 2 need");
  ExpectReadFails("2 2\n0 0 0 -1 1\n0 0 0 1 1\n0 0 0 1 1\n",
                  ":2: the root sphere is unused (radius <= 0)");
  try {
    ReadSph(Out("does-not-exist.sph"));
    ADD_FAILURE();
  } catch (const TreeFileError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be opened"), std::string::npos);
  }
}

TEST(BinaryFormat, RoundTripAndEveryCorruptionIsCaught) {
  const SphereTree& tree = BuiltTree();
  const fs::path p = Out("tree.bin");
  WriteTreeBinary(tree, 42, p);
  ExpectSame(ReadTreeBinary(p, 42), tree);
  EXPECT_THROW(ReadTreeBinary(p, 43), TreeFileError);  // other mesh or parameters

  std::string bytes;
  {
    std::ifstream in(p, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  auto expect_rejected = [&](const std::string& data, const std::string& why) {
    const fs::path q = Out("corrupt.bin");
    std::ofstream(q, std::ios::binary) << data;
    try {
      ReadTreeBinary(q, 42);
      ADD_FAILURE() << "accepted: " << why;
    } catch (const TreeFileError& e) {
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  expect_rejected(flipped, "checksum mismatch");
  expect_rejected(bytes.substr(0, bytes.size() - 9), "truncated");
  expect_rejected(bytes.substr(0, 10), "truncated");
  expect_rejected("NOTATREE" + bytes.substr(8), "not a Sulcus sphere-tree file");
}

}  // namespace
}  // namespace sulcus
