#pragma once
// The YAML reader that every YAML file Sulcus reads shares (scenes, lessons,
// answers, attempt markers): every error is collected
// (never thrown one at a time) as `file:line:column: message`, unknown keys get a
// "did you mean" suggestion, numbers are range-checked with their unit.

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/base/files.h"
#include "core/base/load_error.h"
#include "core/base/text.h"

namespace sulcus {

inline int Levenshtein(const std::string& a, const std::string& b) {
  std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = static_cast<int>(i);
    for (std::size_t j = 1; j <= b.size(); ++j) {
      cur[j] = std::min(
          {prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

// "; did you mean 'x'?" for a close match, else the list of what is expected.
inline std::string Suggest(const std::string& word,
                           const std::vector<std::string>& options) {
  std::string best;
  int best_d = 1 << 30;
  for (const auto& o : options) {
    const int d = Levenshtein(word, o);
    if (d < best_d) {
      best_d = d;
      best = o;
    }
  }
  if (best_d <= std::max<int>(2, static_cast<int>(word.size()) / 3))
    return "; did you mean '" + best + "'?";
  return " (expected one of: " + Join(options) + ")";
}

class YamlReader {
 public:
  /// `kind` names what the file is read as ("lesson file"), for LoadError.
  YamlReader(std::filesystem::path file, std::string kind)
      : file_(std::move(file)), kind_(std::move(kind)) {}
  const std::string& kind() const { return kind_; }
  /// Throws LoadError with every error so far, when there is one.
  void ThrowIfErrors() const {
    if (!errors_.empty()) throw LoadError(kind_, errors_);
  }

  void Error(const YAML::Mark& m, const std::string& message) {
    errors_.push_back({file_.string(), m.line + 1, m.column + 1, ShortenQuoted(message)});
  }
  void Error(const YAML::Node& n, const std::string& message) {
    Error(n.Mark(), message);
  }
  void Error(int line, int column, const std::string& message) {
    errors_.push_back({file_.string(), line, column, ShortenQuoted(message)});
  }
  std::vector<ErrorAt>& errors() { return errors_; }

  // Every key of `map` must be in `allowed`.
  void CheckKeys(const YAML::Node& map, const std::vector<std::string>& allowed,
                 const std::string& where) {
    CheckUnique(map, where);
    for (auto it = map.begin(); it != map.end(); ++it) {
      const std::string key = it->first.Scalar();
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        Error(it->first,
              "unknown key '" + Shorten(key) + "' in " + where + Suggest(key, allowed));
      }
    }
  }

  /// A key given twice in one map (YAML readers keep one of them silently):
  /// an error naming both lines.
  void CheckUnique(const YAML::Node& map, const std::string& where) {
    if (!map.IsMap()) return;
    std::vector<std::pair<std::string, YAML::Mark>> seen;
    for (auto it = map.begin(); it != map.end(); ++it) {
      if (!it->first.IsScalar()) continue;
      const std::string key = it->first.Scalar();
      const auto first = std::find_if(seen.begin(), seen.end(),
                                      [&](const auto& k) { return k.first == key; });
      if (first != seen.end())
        Error(it->first, "'" + Shorten(key) + "' is given twice in " + where +
                             " (first at line " + std::to_string(first->second.line + 1) +
                             "); give it once");
      else
        seen.push_back({key, it->first.Mark()});
    }
  }

  bool IsMap(const YAML::Node& n, const std::string& what) {
    if (n.IsMap()) return true;
    Error(n, what + " must be a map of keys and values");
    return false;
  }

  // A number in [lo, hi]; records an error and returns fallback otherwise.
  double Number(const YAML::Node& n, const std::string& key, double lo, double hi,
                double fallback, const std::string& unit = "") {
    if (!n.IsScalar()) {
      Error(n,
            "'" + key + "' must be a number" + (unit.empty() ? "" : " (" + unit + ")"));
      return fallback;
    }
    double v;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      Error(n, "'" + key + "' must be a number" +
                   (unit.empty() ? "" : " (" + unit + ")") + ", found '" +
                   Shorten(n.Scalar()) + "'");
      return fallback;
    }
    if (!std::isfinite(v) || v < lo || v > hi) {
      Error(n, "'" + key + "' is " + Shorten(n.Scalar()) +
                   (unit.empty() ? "" : " " + unit) + ", expected " + FormatNumber(lo) +
                   " to " + FormatNumber(hi));
      return fallback;
    }
    return v;
  }

  int Integer(const YAML::Node& n, const std::string& key, int lo, int hi, int fallback) {
    const double v = Number(n, key, lo, hi, fallback);
    if (v != std::floor(v)) {
      Error(n,
            "'" + key + "' must be a whole number, found '" + Shorten(n.Scalar()) + "'");
      return fallback;
    }
    return static_cast<int>(v);
  }

  bool Bool(const YAML::Node& n, const std::string& key, bool fallback) {
    bool v = fallback;
    if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) {
      Error(n, "'" + key + "' must be true or false");
      return fallback;
    }
    return v;
  }

  std::string Text(const YAML::Node& n, const std::string& key) {
    if (!n.IsScalar()) {
      Error(n, "'" + key + "' must be text");
      return "";
    }
    return n.Scalar();
  }

  // A list of `count` numbers in [lo, hi].
  bool Numbers(const YAML::Node& n, const std::string& key, std::size_t count, double lo,
               double hi, double* out, const std::string& unit,
               const std::string& meaning) {
    if (!n.IsSequence() || n.size() != count) {
      Error(n, "'" + key + "' must be a list of " + std::to_string(count) + " numbers" +
                   (meaning.empty() ? "" : " (" + meaning + ")") +
                   (n.IsSequence() ? ", found " + std::to_string(n.size()) : ""));
      return false;
    }
    bool ok = true;
    for (std::size_t i = 0; i < count; ++i) {
      const std::size_t before = errors_.size();
      out[i] = Number(n[i], key, lo, hi, 0, unit);
      ok &= errors_.size() == before;
    }
    return ok;
  }

  std::filesystem::path file_;

 private:
  std::string kind_;
  std::vector<ErrorAt> errors_;
};

/// Reads `r`'s file as a YAML map. Throws LoadError, with the file named,
/// when it is missing ("no such " + its kind), unreadable, not YAML, or not a
/// map (`not_a_map` says what it should be).
inline YAML::Node LoadYamlMap(YamlReader& r, const std::string& not_a_map) {
  const std::string& kind = r.kind();
  const std::filesystem::path& file = r.file_;
  // A folder, a FIFO or a device is refused before it is opened (it would
  // block, or never end).
  if (const std::string why = UnreadableReason(file);
      !why.empty() && why != "no such file") {
    r.errors().push_back({file.string(), 0, 0, why});
    r.ThrowIfErrors();
  }
  std::ifstream in(file);
  if (!in) {
    std::error_code ec;
    r.errors().push_back(
        {file.string(), 0, 0,
         std::filesystem::exists(file, ec) ? "cannot be read" : "no such " + kind});
    r.ThrowIfErrors();
  }
  std::stringstream text;
  text << in.rdbuf();
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::Exception& e) {  // syntax, too deep, ...
    r.Error(e.mark, "YAML syntax: " + e.msg);
    r.ThrowIfErrors();
  }
  if (!root.IsMap()) {
    r.Error(root, not_a_map);
    r.ThrowIfErrors();
  }
  return root;
}

}  // namespace sulcus
