// Files a command writes and values shown back in messages: an output never
// resolves to an input however it is spelled, a file is written whole or not at
// all, and a message never echoes a megabyte.
#include "core/base/files.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <random>
#include <sstream>

#include "core/base/names.h"
#include "core/base/text.h"
#include "tests/common/output.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Many spellings of one file: through "." and "..", doubled separators, a
// symlink to its folder, a symlink to it, a hard link, relative to the working
// folder. Every one is refused as an output; a sibling file never is.
TEST(Files, AnOutputNeverResolvesToAnInputHoweverItIsSpelled) {
  const fs::path root = test::FreshOutputPath("files", "spellings");
  fs::create_directories(root / "data" / "sub");
  const fs::path input = root / "data" / "scene.yaml";
  std::ofstream(input) << "objects: []\n";
  std::ofstream(root / "data" / "other.yaml") << "x\n";
  fs::create_directory_symlink(root / "data", root / "via");
  fs::create_symlink(input, root / "link.yaml");
  fs::create_hard_link(input, root / "hard.yaml");
  const std::vector<KeptFile> kept = {{input, "the scene being run"}};
  const std::vector<fs::path> same_bases = {root / "data" / "scene.yaml",
                                            root / "via" / "scene.yaml",
                                            root / "link.yaml", root / "hard.yaml"};
  std::mt19937 rng(7);
  int refused = 0, spellings = 0;
  for (int i = 0; i < 200; ++i) {
    fs::path p = same_bases[rng() % same_bases.size()];
    // Insert "./", "sub/../" or a doubled separator before the file name.
    std::string s = p.parent_path().string();
    for (int k = rng() % 4; k > 0; --k) {
      switch (rng() % 3) {
        case 0:
          s += "/.";
          break;
        case 1:
          s += "/sub/..";
          break;
        default:
          s += "/";
          break;
      }
    }
    // "sub/.." only exists below data/: elsewhere it is not a spelling of the file.
    if (s.find("sub") != std::string::npos && !fs::exists(fs::path(s))) continue;
    const fs::path spelled = s + "/" + p.filename().string();
    ++spellings;
    try {
      RefuseOverwrite(spelled, kept);
    } catch (const FileError& e) {
      ++refused;
      EXPECT_NE(std::string(e.what()).find("it is the scene being run"),
                std::string::npos);
    }
  }
  EXPECT_GT(spellings, 100);
  EXPECT_EQ(refused, spellings);
  // Relative to the working folder.
  const fs::path before = fs::current_path();
  fs::current_path(root / "data" / "sub");
  EXPECT_THROW(RefuseOverwrite("../scene.yaml", kept), FileError);
  EXPECT_NO_THROW(RefuseOverwrite("../other.yaml", kept));
  EXPECT_NO_THROW(RefuseOverwrite("../new.yaml", kept));
  fs::current_path(before);
  EXPECT_NO_THROW(RefuseOverwrite(root / "data" / "other.yaml", kept));
  EXPECT_EQ(Read(input), "objects: []\n");
}

TEST(Files, AFileIsWrittenWholeOrNotAtAll) {
  const fs::path root = test::FreshOutputPath("files", "atomic");
  const fs::path out = root / "report.json";
  std::ofstream(out) << "old";
  {
    AtomicFile f(out);
    f.stream() << "new, never committed";
  }
  EXPECT_EQ(Read(out), "old") << "dropped without Commit, the old file stays";
  {
    AtomicFile f(out);
    f.stream() << "new";
    f.Commit();
  }
  EXPECT_EQ(Read(out), "new");
  for (const auto& e : fs::directory_iterator(root))
    EXPECT_EQ(e.path().filename(), "report.json") << "a temporary file was left behind";
  if (fs::exists("/dev/full")) {
    AtomicFile full("/dev/full");
    full.stream() << std::string(1 << 16, 'x');
    EXPECT_THROW(full.Commit(), FileError) << "a full disk is an error";
  }
  EXPECT_THROW(AtomicFile{root}, FileError) << "a folder is not a file";
}

TEST(Files, InsideAFolderIsDecidedWithLinksFollowedComponentByComponent) {
  const fs::path root = test::FreshOutputPath("files", "inside");
  fs::create_directories(root / "scenes");
  fs::create_directories(root / "scenes2");
  std::ofstream(root / "scenes2" / "m.stl") << "x";
  std::ofstream(root / "outside.stl") << "x";
  fs::create_symlink(root / "outside.stl", root / "scenes" / "link.stl");
  EXPECT_TRUE(IsInsideFolder(root / "scenes" / "m.stl", root / "scenes"));
  EXPECT_FALSE(IsInsideFolder(root / "scenes2" / "m.stl", root / "scenes"))
      << "a folder whose name starts alike is another folder";
  EXPECT_FALSE(IsInsideFolder(root / "scenes" / "link.stl", root / "scenes"))
      << "a link out of the folder is outside";
  EXPECT_FALSE(IsInsideFolder(root / "scenes" / ".." / "outside.stl", root / "scenes"));
  const fs::path before = fs::current_path();
  fs::current_path(root / "scenes");
  EXPECT_TRUE(IsInsideFolder("m.stl", "."));
  fs::current_path(before);
}

// What a terminal shows of a name from the store: a newline cannot forge a
// row, an escape cannot clear the screen, a right-to-left override cannot turn
// the line round; letters of every script pass as they are.
TEST(Text, TerminalSafeEscapesControlsAndDirectionOverrides) {
  EXPECT_EQ(TerminalSafe("Zo\xC3\xAB \xE6\x9D\x8E"), "Zo\xC3\xAB \xE6\x9D\x8E");
  EXPECT_EQ(TerminalSafe("eve\nalice ... 100.0"), "eve\\x0Aalice ... 100.0");
  EXPECT_EQ(TerminalSafe("\x1b[2Jbob"), "\\x1B[2Jbob");
  EXPECT_EQ(TerminalSafe("ali\xE2\x80\xAE"
                         "ecila"),
            "ali\\u{202E}ecila");
  EXPECT_EQ(TerminalSafe("bad \xff byte"), "bad \\xFF byte");
  EXPECT_EQ(TerminalSafe("\xC2\x85"), "\\x85") << "a C1 control";
}

// A student's name is refused where it is typed, with the reason.
TEST(Text, ANameIsCheckedAtTheDoor) {
  EXPECT_EQ(NameProblem("Ada Lovelace"), "");
  EXPECT_EQ(NameProblem("Zo\xC3\xAB"), "");
  EXPECT_NE(NameProblem(""), "");
  EXPECT_NE(NameProblem("eve\nalice"), "");
  EXPECT_NE(NameProblem("\x1b[2J"), "");
  EXPECT_NE(NameProblem("ali\xE2\x80\xAE"
                        "ce"),
            "");
  EXPECT_NE(NameProblem("bad \xff"), "");
  EXPECT_NE(NameProblem("\xC0\xAF"), "") << "an overlong form";
  EXPECT_EQ(NameProblem(std::string(kMaxNameChars, 'a')), "");
  EXPECT_NE(NameProblem(std::string(kMaxNameChars + 1, 'a')).find("121 characters"),
            std::string::npos);
  std::string wide;
  for (std::size_t i = 0; i < kMaxNameChars; ++i) wide += "\xC3\xA9";
  EXPECT_EQ(NameProblem(wide), "") << "characters, not bytes";
}

// One spelling per student: trimmed and composed, whatever the keyboard sent;
// invisible characters and look-alikes refused with the reason.
TEST(Text, ANameHasOneSpellingAndLookAlikesAreRefused) {
  EXPECT_EQ(NormalName("  Zoe\xCC\x88 \xC2\xA0"), "Zo\xC3\xAB")
      << "trimmed (a no-break space too) and composed";
  EXPECT_EQ(NameProblem(NormalName("Zoe\xCC\x88")), "");
  EXPECT_NE(NameProblem("Zoe\xCC\x88").find("composed"), std::string::npos)
      << "a decomposed name is refused as it stands (callers normalise first)";
  EXPECT_NE(NameProblem("alice ").find("white space"), std::string::npos);
  EXPECT_NE(NameProblem("ali\xE2\x80\x8B"
                        "ce")
                .find("invisible"),
            std::string::npos)
      << "a zero-width space";
  EXPECT_NE(NameProblem("\xD0\xB0lice").find("alphabets"), std::string::npos)
      << "a Cyrillic a among Latin letters";
  EXPECT_EQ(NameProblem("\xD0\x90\xD0\xBB\xD0\xB8\xD1\x81\xD0\xB0"), "")
      << "a name in one alphabet (Cyrillic) is a name";
  EXPECT_EQ(NameProblem("Jos\xC3\xA9 Mar\xC3\xAD"
                        "a O'Neil-Garc\xC3\xAD"
                        "a"),
            "");
  EXPECT_EQ(NameProblem("\xE5\xB1\xB1\xE7\x94\xB0 Taro"), "") << "Han with Latin";
  EXPECT_EQ(NameLookAlikeKey("alice"), NameLookAlikeKey("\xD0\xB0lice"));
  EXPECT_EQ(NameLookAlikeKey("Alice"), NameLookAlikeKey("alice")) << "case aside";
  EXPECT_EQ(NameLookAlikeKey("aIice"), NameLookAlikeKey("alice"));
  EXPECT_NE(NameLookAlikeKey("alice"), NameLookAlikeKey("alina"));
}

TEST(Text, LongValuesAreCutAndNumbersReadable) {
  EXPECT_EQ(Shorten("short"), "short");
  const std::string mb(1 << 20, 'x');
  const std::string cut = Shorten(mb);
  EXPECT_EQ(cut, std::string(80, 'x') + "... (1048576 characters)");
  EXPECT_EQ(Shorten(std::string("a\0b\n", 4)), "a?b?");
  // Never inside a UTF-8 character: 41 two-byte letters cut at 80 bytes.
  std::string accents;
  for (int i = 0; i < 41; ++i) accents += "\xC3\xA9";
  EXPECT_EQ(Shorten(accents).substr(0, 80), accents.substr(0, 80));
  std::string odd = "x" + accents;  // the 80th byte is a character's first
  EXPECT_EQ(Shorten(odd).find("... ("), 79u);
  EXPECT_EQ(ShortenQuoted("unknown tissue '" + mb + "'; did you mean 'bone'?"),
            "unknown tissue '" + std::string(80, 'x') +
                "... (1048576 characters)'; did you mean 'bone'?");
  EXPECT_EQ(FormatNumber(1e308), "1e+308");
  EXPECT_EQ(FormatNumber(0.25), "0.25");
}

TEST(Text, AListInAMessageIsJoinedByCommas) {
  EXPECT_EQ(Join(std::vector<std::string>{"careful", "rough"}), "careful, rough");
  EXPECT_EQ(Join(std::vector<int>{47, 46, 45}), "47, 46, 45");
  EXPECT_EQ(Join(std::vector<int>{}), "");
}

}  // namespace
}  // namespace sulcus
