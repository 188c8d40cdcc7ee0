// The HTML report: every element id is given once, and every link to a moment
// of the attempt ("#t<tick>") has its target, also when lines share a tick.
#include "core/lesson/report.h"

#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>
#include <string>

namespace sulcus {
namespace {

TEST(Report, IdsAreUniqueAndEveryMomentLinkHasItsTarget) {
  LessonResult r;
  for (const std::uint64_t tick : {1200u, 1200u, 1200u, 4800u}) {
    RubricLine l;
    l.category = "force";
    l.status = RubricLine::Status::kPass;
    l.credit = 1;
    l.message = "a line at tick " + std::to_string(tick);
    l.tick = tick;
    r.lines.push_back(l);
  }
  const std::string html = ReportHtml(r, {});
  std::map<std::string, int> ids;
  const std::regex id(" id=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), id);
       it != std::sregex_iterator(); ++it)
    ++ids[(*it)[1]];
  ASSERT_FALSE(ids.empty());
  for (const auto& [name, count] : ids) EXPECT_EQ(count, 1) << "id " << name;
  const std::regex link("href=\"#(t[0-9]+)\"");
  std::set<std::string> targets;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), link);
       it != std::sregex_iterator(); ++it)
    targets.insert((*it)[1]);
  EXPECT_EQ(targets, (std::set<std::string>{"t1200", "t4800"}));
  for (const std::string& t : targets) EXPECT_EQ(ids.count(t), 1u) << t;
}

}  // namespace
}  // namespace sulcus
