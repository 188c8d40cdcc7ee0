#include "core/geometry/mesh_readers.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_map>

#include "core/base/text.h"
#include "core/geometry/mesh.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

constexpr std::uintmax_t kMaxFileBytes = 2ull << 30;  // 2 GiB: far beyond any tooth scan

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string ReadAll(const fs::path& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw MeshError(path.string(), "cannot be read: " + ec.message());
  if (size > kMaxFileBytes)
    throw MeshError(path.string(), "is " + std::to_string(size >> 20) +
                                       " MiB; a mesh file may be at most 2048 MiB");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw MeshError(path.string(), "cannot be opened for reading (check permissions)");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size)
    throw MeshError(path.string(), "could not be read to its end");
  return bytes;
}

// Whitespace-separated tokens of a text file, each with its line.
class Tokens {
 public:
  Tokens(const std::string& text, const fs::path& path) : s_(text), path_(path) {}
  bool Next(std::string_view* token) {
    SkipSpace(true);
    if (pos_ >= s_.size()) return false;
    const std::size_t start = pos_;
    while (pos_ < s_.size() && !std::isspace(static_cast<unsigned char>(s_[pos_])))
      ++pos_;
    *token = std::string_view(s_).substr(start, pos_ - start);
    return true;
  }
  // The rest of the current line (for headers, comments and skipped records).
  std::string_view RestOfLine() {
    const std::size_t start = pos_;
    while (pos_ < s_.size() && s_[pos_] != '\n') ++pos_;
    std::string_view v = std::string_view(s_).substr(start, pos_ - start);
    if (!v.empty() && v.back() == '\r') v.remove_suffix(1);
    return v;
  }
  // The next line's tokens (empty lines and lines starting with '#' skipped); false at
  // the end.
  bool NextLine(std::vector<std::string_view>* tokens) {
    tokens->clear();
    while (pos_ < s_.size()) {
      if (at_line_start_) ++line_;
      at_line_start_ = false;
      std::string_view l = RestOfLine();
      if (pos_ < s_.size()) {
        ++pos_;  // the '\n'
        at_line_start_ = true;
      }
      std::size_t i = 0;
      while (i < l.size()) {
        while (i < l.size() && std::isspace(static_cast<unsigned char>(l[i]))) ++i;
        if (i < l.size() && l[i] == '#') break;
        const std::size_t b = i;
        while (i < l.size() && !std::isspace(static_cast<unsigned char>(l[i]))) ++i;
        if (i > b) tokens->push_back(l.substr(b, i - b));
      }
      if (!tokens->empty()) return true;
    }
    return false;
  }
  std::size_t pos() const { return pos_; }
  int line() const { return line_; }  // of the last token or line read
  void Seek(std::size_t p, int line) {
    pos_ = p;
    line_ = line;
  }
  [[noreturn]] void Fail(const std::string& what) const {
    throw MeshError(path_.string(),
                    "line " + std::to_string(line_) + ": " + ShortenQuoted(what));
  }

 private:
  void SkipSpace(bool count_lines) {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) {
      if (count_lines && s_[pos_] == '\n') ++line_;
      ++pos_;
    }
    if (line_ == 0) line_ = 1;
  }
  const std::string& s_;
  const fs::path& path_;
  std::size_t pos_ = 0;
  int line_ = 0;
  bool at_line_start_ = true;
};

bool ParseDouble(std::string_view t, double* v) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  // from_chars for double is in libstdc++ 11+; it never reads past the token.
  const auto r = std::from_chars(t.data(), t.data() + t.size(), *v);
  if (r.ec == std::errc::result_out_of_range) {
    *v = std::numeric_limits<double>::infinity();  // reported as non-finite
    return r.ptr == t.data() + t.size();
  }
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

bool ParseInt(std::string_view t, long long* v) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), *v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

int CheckedIndex(long long v, const Tokens& tok) {
  if (v < std::numeric_limits<int>::min() / 2 || v > std::numeric_limits<int>::max() / 2)
    tok.Fail("vertex index " + std::to_string(v) + " is out of range");
  return static_cast<int>(v);
}

Vector3 Point3(const std::vector<std::string_view>& t, std::size_t from,
               const Tokens& tok, const char* what) {
  if (t.size() < from + 3)
    tok.Fail(std::string(what) + ": expected three coordinates x y z");
  Vector3 p;
  for (int k = 0; k < 3; ++k) {
    double v;
    if (!ParseDouble(t[from + k], &v))
      tok.Fail(std::string(what) + ": '" + std::string(t[from + k]) +
               "' is not a number");
    if (!std::isfinite(v))
      tok.Fail(std::string(what) + ": a non-finite coordinate (NaN or infinity)");
    p[k] = v;
  }
  return p;
}

// ---- STL -------------------------------------------------------------------

struct PointHash {
  std::size_t operator()(const std::array<std::uint64_t, 3>& k) const {
    return std::hash<std::uint64_t>()(k[0] * 0x9E3779B97F4A7C15ull ^
                                      (k[1] + 0x632BE59BD9B4E019ull) * 31 ^ k[2]);
  }
};

class Merger {
 public:
  explicit Merger(RawMesh* m) : m_(m) {}
  int Add(const Vector3& p) {
    std::array<std::uint64_t, 3> key;
    for (int k = 0; k < 3; ++k)
      key[k] = std::bit_cast<std::uint64_t>(p[k] == 0.0 ? 0.0 : p[k]);  // -0 == +0
    const auto [it, fresh] = index_.try_emplace(key, static_cast<int>(m_->points.size()));
    if (fresh) m_->points.push_back(p);
    return it->second;
  }

 private:
  RawMesh* m_;
  std::unordered_map<std::array<std::uint64_t, 3>, int, PointHash> index_;
};

RawMesh ReadBinaryStl(const std::string& b, const fs::path& path) {
  std::uint32_t count = 0;
  std::memcpy(&count, b.data() + 80, 4);
  const std::uintmax_t expected = 84 + 50ull * count;
  if (b.size() < expected)
    throw MeshError(path.string(), "truncated binary STL: the header declares " +
                                       std::to_string(count) + " triangles (" +
                                       std::to_string(expected) +
                                       " bytes) but the file has " +
                                       std::to_string(b.size()) + " bytes");
  RawMesh m;
  m.polygons.reserve(count);
  Merger merge(&m);
  for (std::uint32_t t = 0; t < count; ++t) {
    float record[12];
    std::memcpy(record, b.data() + 84 + 50ull * t, sizeof record);
    std::vector<int> tri;
    for (int c = 0; c < 3; ++c) {
      const Vector3 p(record[3 + 3 * c], record[4 + 3 * c], record[5 + 3 * c]);
      if (!p.allFinite())
        throw MeshError(path.string(),
                        "triangle " + std::to_string(t) + " corner " + std::to_string(c) +
                            " has a non-finite coordinate (NaN or infinity)");
      tri.push_back(merge.Add(p));
    }
    m.polygons.push_back(std::move(tri));
  }
  return m;
}

RawMesh ReadAsciiStl(const std::string& text, const fs::path& path) {
  Tokens tok(text, path);
  RawMesh m;
  Merger merge(&m);
  std::vector<std::string_view> t;
  std::vector<int> corners;
  bool in_loop = false, ended = false;
  while (tok.NextLine(&t)) {
    const std::string key = Lower(std::string(t[0]));
    if (key == "solid" || key == "facet" || key == "endfacet") {
      if (in_loop)
        tok.Fail("'" + key + "' inside a loop: expected 'endloop' after three vertices");
      if (key == "solid") ended = false;
    } else if (key == "outer") {
      if (in_loop) tok.Fail("'outer loop' inside a loop");
      in_loop = true;
      corners.clear();
    } else if (key == "vertex") {
      if (!in_loop) tok.Fail("'vertex' outside 'outer loop' ... 'endloop'");
      if (corners.size() == 3)
        tok.Fail("a fourth vertex in a facet: ASCII STL facets are triangles");
      corners.push_back(merge.Add(Point3(t, 1, tok, "vertex")));
    } else if (key == "endloop") {
      if (!in_loop) tok.Fail("'endloop' without 'outer loop'");
      if (corners.size() != 3)
        tok.Fail("a facet with " + std::to_string(corners.size()) +
                 " vertices, expected 3");
      m.polygons.push_back(corners);
      in_loop = false;
    } else if (key == "endsolid") {
      ended = true;
    } else {
      tok.Fail("'" + std::string(t[0]) +
               "': expected facet, outer loop, vertex, endloop, endfacet or endsolid");
    }
  }
  if (in_loop)
    throw MeshError(path.string(), "ends inside a facet (truncated ASCII STL)");
  if (!ended && !m.polygons.empty())
    throw MeshError(path.string(), "ends without 'endsolid' (truncated ASCII STL)");
  return m;
}

RawMesh ReadStl(const std::string& b, const fs::path& path) {
  std::size_t i = 0;
  while (i < b.size() && std::isspace(static_cast<unsigned char>(b[i]))) ++i;
  const bool says_solid = b.compare(i, 5, "solid") == 0;
  if (b.size() >= 84) {
    std::uint32_t count = 0;
    std::memcpy(&count, b.data() + 80, 4);
    // A binary file's size is exactly its count's; "solid" may begin a binary header.
    if (84 + 50ull * count == b.size() || !says_solid) return ReadBinaryStl(b, path);
  }
  if (!says_solid)
    throw MeshError(path.string(),
                    "truncated binary STL: no triangle count after the 80-byte header");
  return ReadAsciiStl(b, path);
}

// ---- OBJ -------------------------------------------------------------------

RawMesh ReadObj(const std::string& text, const fs::path& path) {
  Tokens tok(text, path);
  RawMesh m;
  std::vector<std::string_view> t;
  while (tok.NextLine(&t)) {
    if (t[0] == "v") {
      m.points.push_back(Point3(t, 1, tok, "vertex"));
    } else if (t[0] == "f") {
      if (t.size() < 4)
        tok.Fail("a face needs 3 or more vertices, found " +
                 std::to_string(t.size() - 1));
      std::vector<int> poly;
      poly.reserve(t.size() - 1);
      for (std::size_t k = 1; k < t.size(); ++k) {
        const std::string_view idx = t[k].substr(0, t[k].find('/'));
        long long v;
        if (!ParseInt(idx, &v))
          tok.Fail("face vertex '" + std::string(t[k]) + "' is not an index");
        if (v == 0) tok.Fail("face vertex index 0: OBJ counts vertices from 1");
        // Negative: relative to the vertices read so far.
        if (v < 0)
          v += static_cast<long long>(m.points.size());
        else
          v -= 1;
        poly.push_back(CheckedIndex(v, tok));
      }
      m.polygons.push_back(std::move(poly));
    }
    // vn, vt, o, g, s, l, p, usemtl, mtllib and the rest say nothing about the surface.
  }
  return m;
}

// ---- OFF -------------------------------------------------------------------

RawMesh ReadOff(const std::string& text, const fs::path& path) {
  Tokens tok(text, path);
  std::vector<std::string_view> t;
  if (!tok.NextLine(&t))
    throw MeshError(path.string(), "is empty, expected the OFF header");
  std::size_t at = 0;
  const std::string head = std::string(t[0]);
  if (head.size() < 3 || head.substr(head.size() - 3) != "OFF")
    tok.Fail("expected the header 'OFF', found '" + head + "'");
  if (head != "OFF" && head != "COFF" && head != "NOFF" && head != "CNOFF")
    tok.Fail("'" + head +
             "' is an OFF variant Sulcus does not read (OFF, COFF, NOFF, CNOFF)");
  ++at;
  if (at >= t.size()) {  // the counts on the next line
    if (!tok.NextLine(&t))
      throw MeshError(path.string(), "ends after its header, expected the counts");
    at = 0;
  }
  if (t.size() < at + 2) tok.Fail("expected the counts: vertices faces [edges]");
  long long nv, nf;
  if (!ParseInt(t[at], &nv) || !ParseInt(t[at + 1], &nf) || nv < 0 || nf < 0)
    tok.Fail("expected the counts as whole numbers: vertices faces [edges]");
  // Each vertex and face takes at least a line of a few characters.
  const long long room = static_cast<long long>(text.size());
  if (nv > room / 4 || nf > room / 4)
    tok.Fail("the header declares " + std::to_string(nv) + " vertices and " +
             std::to_string(nf) + " faces, more than a file of " +
             std::to_string(text.size()) + " bytes can hold");
  RawMesh m;
  m.points.reserve(static_cast<std::size_t>(nv));
  m.polygons.reserve(static_cast<std::size_t>(nf));
  for (long long i = 0; i < nv; ++i) {
    if (!tok.NextLine(&t))
      throw MeshError(path.string(), "ends after " + std::to_string(i) + " of its " +
                                         std::to_string(nv) + " vertices");
    m.points.push_back(Point3(t, 0, tok, "vertex"));
  }
  for (long long i = 0; i < nf; ++i) {
    if (!tok.NextLine(&t))
      throw MeshError(path.string(), "ends after " + std::to_string(i) + " of its " +
                                         std::to_string(nf) + " faces");
    long long k;
    if (!ParseInt(t[0], &k) || k < 0)
      tok.Fail("a face starts with its vertex count, found '" + std::string(t[0]) + "'");
    if (static_cast<std::size_t>(k) + 1 > t.size())
      tok.Fail("a face of " + std::to_string(k) + " vertices lists " +
               std::to_string(t.size() - 1));
    std::vector<int> poly;
    for (long long j = 0; j < k; ++j) {
      long long v;
      if (!ParseInt(t[static_cast<std::size_t>(j + 1)], &v))
        tok.Fail("face vertex '" + std::string(t[j + 1]) + "' is not an index");
      poly.push_back(CheckedIndex(v, tok));
    }
    m.polygons.push_back(std::move(poly));
  }
  return m;
}

// ---- PLY -------------------------------------------------------------------

enum class PlyType {
  kInt8,
  kUint8,
  kInt16,
  kUint16,
  kInt32,
  kUint32,
  kFloat32,
  kFloat64
};

bool PlyTypeOf(std::string_view s, PlyType* t) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},
      {"uchar", PlyType::kUint8},    {"uint8", PlyType::kUint8},
      {"short", PlyType::kInt16},    {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16},  {"uint16", PlyType::kUint16},
      {"int", PlyType::kInt32},      {"int32", PlyType::kInt32},
      {"uint", PlyType::kUint32},    {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32},
      {"double", PlyType::kFloat64}, {"float64", PlyType::kFloat64}};
  for (const auto& [n, v] : names)
    if (s == n) {
      *t = v;
      return true;
    }
  return false;
}

std::size_t PlySize(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 1;
}

struct PlyProperty {
  std::string name;
  bool list = false;
  PlyType count_type = PlyType::kUint8, type = PlyType::kFloat32;
};
struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> props;
};

class PlyBody {
 public:
  PlyBody(const std::string& b, std::size_t start, int header_lines, int format,
          const fs::path& path)
      : b_(b), pos_(start), format_(format), path_(path), tok_(b, path) {
    tok_.Seek(start, header_lines);
  }
  std::size_t remaining() const { return b_.size() - pos_; }
  bool ascii() const { return format_ == 0; }
  double Read(PlyType t, const char* what) {
    if (ascii()) {
      std::string_view token;
      if (!tok_.Next(&token)) Fail(std::string("ends early: expected ") + what);
      double v;
      if (!ParseDouble(token, &v))
        Fail(std::string(what) + ": '" + std::string(token) + "' is not a number");
      return v;
    }
    const std::size_t n = PlySize(t);
    if (remaining() < n) Fail(std::string("ends early: expected ") + what);
    unsigned char raw[8];
    std::memcpy(raw, b_.data() + pos_, n);
    if (format_ == 2) std::reverse(raw, raw + n);  // big endian
    pos_ += n;
    switch (t) {
      case PlyType::kInt8:
        return static_cast<std::int8_t>(raw[0]);
      case PlyType::kUint8:
        return raw[0];
      case PlyType::kInt16: {
        std::int16_t v;
        std::memcpy(&v, raw, 2);
        return v;
      }
      case PlyType::kUint16: {
        std::uint16_t v;
        std::memcpy(&v, raw, 2);
        return v;
      }
      case PlyType::kInt32: {
        std::int32_t v;
        std::memcpy(&v, raw, 4);
        return v;
      }
      case PlyType::kUint32: {
        std::uint32_t v;
        std::memcpy(&v, raw, 4);
        return v;
      }
      case PlyType::kFloat32: {
        float v;
        std::memcpy(&v, raw, 4);
        return v;
      }
      case PlyType::kFloat64: {
        double v;
        std::memcpy(&v, raw, 8);
        return v;
      }
    }
    return 0;
  }
  [[noreturn]] void Fail(const std::string& what) const {
    if (ascii()) tok_.Fail(what);
    throw MeshError(path_.string(),
                    "byte " + std::to_string(pos_) + ": " + ShortenQuoted(what));
  }
  std::size_t size() const { return b_.size(); }

 private:
  const std::string& b_;
  std::size_t pos_;
  int format_;  // 0 ascii, 1 little endian, 2 big endian
  const fs::path& path_;
  Tokens tok_;
};

RawMesh ReadPly(const std::string& b, const fs::path& path) {
  // The header: text lines up to end_header.
  Tokens header(b, path);
  auto fail = [&](const std::string& what) { header.Fail(what); };
  std::vector<std::string_view> t;
  if (!header.NextLine(&t) || t.size() != 1 || t[0] != "ply")
    fail("expected 'ply' as the first line");
  int format = -1;
  std::vector<PlyElement> elements;
  bool header_done = false;
  while (header.NextLine(&t)) {
    const std::vector<std::string> w(t.begin(), t.end());
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      header_done = true;
      break;
    }
    if (w[0] == "format") {
      if (w.size() < 2)
        fail("expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
      format = w[1] == "ascii"                  ? 0
               : w[1] == "binary_little_endian" ? 1
               : w[1] == "binary_big_endian"    ? 2
                                                : -2;
      if (format == -2) fail("unknown PLY format '" + w[1] + "'");
    } else if (w[0] == "element") {
      long long n;
      if (w.size() != 3 || !ParseInt(w[2], &n) || n < 0)
        fail("expected 'element NAME COUNT'");
      elements.push_back({w[1], n, {}});
    } else if (w[0] == "property") {
      if (elements.empty()) fail("a property before any element");
      PlyProperty p;
      if (w.size() == 5 && w[1] == "list") {
        p.list = true;
        if (!PlyTypeOf(w[2], &p.count_type) || !PlyTypeOf(w[3], &p.type))
          fail("unknown property type in 'property list " + w[2] + " " + w[3] + "'");
        if (p.count_type == PlyType::kFloat32 || p.count_type == PlyType::kFloat64)
          fail("a list's count must be an integer type");
        p.name = w[4];
      } else if (w.size() == 3) {
        if (!PlyTypeOf(w[1], &p.type)) fail("unknown property type '" + w[1] + "'");
        p.name = w[2];
      } else {
        fail("expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME'");
      }
      elements.back().props.push_back(p);
    } else {
      fail("'" + w[0] + "': expected format, element, property, comment or end_header");
    }
  }
  if (!header_done) throw MeshError(path.string(), "the PLY header has no 'end_header'");
  if (format < 0) throw MeshError(path.string(), "the PLY header has no 'format' line");

  PlyBody body(b, header.pos(), header.line(), format, path);
  RawMesh m;
  for (const PlyElement& e : elements) {
    // The least room each record takes, against what is left, before any loop.
    std::size_t least = 0;
    for (const PlyProperty& p : e.props)
      least += format == 0 ? 2 : p.list ? PlySize(p.count_type) : PlySize(p.type);
    if (e.count > 0 && least == 0)
      body.Fail("element '" + e.name + "' declares " + std::to_string(e.count) +
                " records without properties");
    if (least > 0 && static_cast<std::uintmax_t>(e.count) >
                         body.remaining() / least + (format == 0 ? 1 : 0))
      body.Fail("element '" + e.name + "' declares " + std::to_string(e.count) +
                " records; the " + std::to_string(body.remaining()) +
                " bytes left can hold at most " +
                std::to_string(body.remaining() / least));
    const bool vertex = e.name == "vertex", face = e.name == "face";
    int ix = -1, iy = -1, iz = -1, ilist = -1;
    for (std::size_t k = 0; k < e.props.size(); ++k) {
      const std::string& n = e.props[k].name;
      if (n == "x") ix = static_cast<int>(k);
      if (n == "y") iy = static_cast<int>(k);
      if (n == "z") iz = static_cast<int>(k);
      if (e.props[k].list && ilist < 0 && (n == "vertex_indices" || n == "vertex_index"))
        ilist = static_cast<int>(k);
    }
    if (vertex && (ix < 0 || iy < 0 || iz < 0 || e.props[ix].list || e.props[iy].list ||
                   e.props[iz].list))
      body.Fail("the vertex element has no x, y and z properties");
    if (face && ilist < 0) body.Fail("the face element has no 'vertex_indices' list");
    if (vertex) m.points.reserve(static_cast<std::size_t>(e.count));
    if (face) m.polygons.reserve(static_cast<std::size_t>(e.count));
    for (long long r = 0; r < e.count; ++r) {
      Vector3 p = Vector3::Zero();
      std::vector<int> poly;
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const PlyProperty& pr = e.props[k];
        if (!pr.list) {
          const double v = body.Read(pr.type, "a property value");
          if (vertex && static_cast<int>(k) == ix) p.x() = v;
          if (vertex && static_cast<int>(k) == iy) p.y() = v;
          if (vertex && static_cast<int>(k) == iz) p.z() = v;
          continue;
        }
        const double c = body.Read(pr.count_type, "a list's count");
        if (!std::isfinite(c) || c < 0 || c != std::floor(c))
          body.Fail("a list's count must be a whole number >= 0");
        const std::size_t item = format == 0 ? 2 : PlySize(pr.type);
        if (c > static_cast<double>(body.remaining() / item + 1))
          body.Fail("a list of " +
                    std::to_string(static_cast<unsigned long long>(std::min(c, 1e19))) +
                    " items is longer than the file");
        const long long count = static_cast<long long>(c);
        for (long long j = 0; j < count; ++j) {
          const double v = body.Read(pr.type, "a list item");
          if (face && static_cast<int>(k) == ilist) {
            if (v != std::floor(v) || std::abs(v) > std::numeric_limits<int>::max() / 2)
              body.Fail("vertex index " + std::to_string(v) + " is not a valid index");
            poly.push_back(static_cast<int>(v));
          }
        }
      }
      if (vertex) {
        if (!p.allFinite())
          body.Fail("vertex " + std::to_string(r) +
                    " has a non-finite coordinate (NaN or infinity)");
        m.points.push_back(p);
      }
      if (face) m.polygons.push_back(std::move(poly));
    }
  }
  return m;
}

}  // namespace

RawMesh ReadMeshFile(const fs::path& path) {
  const std::string bytes = ReadAll(path);
  const std::string ext = Lower(path.extension().string());
  if (ext == ".stl") return ReadStl(bytes, path);
  if (ext == ".obj") return ReadObj(bytes, path);
  if (ext == ".off") return ReadOff(bytes, path);
  if (ext == ".ply") return ReadPly(bytes, path);
  throw MeshError(path.string(), "unsupported extension '" + path.extension().string() +
                                     "' (expected .stl, .obj, .ply or .off)");
}

}  // namespace sulcus
