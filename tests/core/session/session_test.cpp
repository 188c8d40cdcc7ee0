// The session hands every tick to every consumer, in order, live and offline;
// and a compiled scene keeps each object's own sphere-tree settings even when
// soft objects are moved behind the hard ones.
#include "core/session/session.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "tests/common/output.h"

namespace sulcus {
namespace {

namespace fs = std::filesystem;

fs::path Out(const std::string& name) { return test::OutputPath("session", name); }

struct Collector final : TickConsumer {
  void OnTick(const TickRecord& r) override {
    if (!ticks.empty() && r.tick != ticks.back() + 1) ++gaps;
    ticks.push_back(r.tick);
  }
  void OnEnd() override { ++ends; }
  std::vector<std::uint64_t> ticks;
  int gaps = 0, ends = 0;
};

std::unique_ptr<CompiledScene> Block() {
  const fs::path scene = Out("block.yaml");
  std::ofstream(scene) << "spheretree: {levels: 3, leaves: 16}\n"
                          "objects:\n"
                          "  - box: [10, 10, 4]\n"
                          "    tissue: bone\n";
  return CompileScene(LoadSceneSpec(scene), Out("cache"));
}

TEST(Session, EveryConsumerGetsEveryTickInOrderOffline) {
  const auto scene = Block();
  DeviceSpec d = MakeDevice("scripted:poke", *scene, 0.5);
  SessionOptions so;
  so.max_ticks = 400;
  so.record = Out("offline.rec");
  Session session(*scene, std::move(d), so);
  Collector a, b;
  session.AddConsumer(&a);
  session.AddConsumer(&b);
  session.RunOffline();
  EXPECT_EQ(a.ticks.size(), 400u);
  EXPECT_EQ(a.ticks, b.ticks);
  EXPECT_EQ(a.gaps, 0);
  EXPECT_EQ(a.ends, 1);
  EXPECT_EQ(ReadRecording(Out("offline.rec")).frames.size(), 400u)
      << "the recorder is a consumer too";
}

TEST(Session, LiveTicksReachTheConsumersOffTheHapticThread) {
  const auto scene = Block();
  SessionOptions so;
  so.max_ticks = 300;
  so.realtime = false;
  Session session(*scene, MakeDevice("scripted:poke", *scene, 0.5), so);
  Collector c;
  session.AddConsumer(&c);
  session.Start();
  while (session.running()) {
    session.Pump();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  session.Stop();
  EXPECT_EQ(c.ticks.size(), 300u);
  EXPECT_EQ(c.gaps, 0);
  EXPECT_EQ(c.ends, 1);
  EXPECT_EQ(session.dropped_ticks(), 0u);
}

// A free-running thread refills the ring as fast as a consumer drains it: one
// Pump hands at most a ring's worth and returns, so the window's timer is not
// held for as long as the thread can go.
TEST(Session, OnePumpOfAFreeRunningThreadIsBounded) {
  const auto scene = Block();
  SessionOptions so;
  so.max_ticks = 200000;
  so.realtime = false;
  so.free_run = true;
  Session session(*scene, MakeDevice("scripted:poke", *scene, 300), so);
  struct Slow final : TickConsumer {
    std::uint64_t n = 0;
    void OnTick(const TickRecord&) override {
      ++n;
      if (n % 64 == 0)
        std::this_thread::sleep_for(
            std::chrono::microseconds(50));  // slower than the thread
    }
  } slow;
  session.AddConsumer(&slow);
  session.Start();
  while (slow.n == 0) {
    session.Pump();
    std::this_thread::yield();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the ring fills
  const std::size_t one = session.Pump();
  EXPECT_LE(one, 16384u) << "one pump: at most a ring's worth";
  EXPECT_GT(one, 0u);
  session.Stop();
  EXPECT_EQ(session.dropped_ticks(), 0u) << "free run waits for room, it drops nothing";
  EXPECT_EQ(slow.n, session.ticks_delivered());
}

TEST(Session, DeviceSpellingsAreCheckedWithAClearError) {
  const auto scene = Block();
  try {
    MakeDevice("phantom", *scene, 1);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(
        std::string(e.what()).find("a device is mouse, scripted:NAME, "
                                   "scripted:FILE.csv, replay:FILE or student:NAME"),
        std::string::npos)
        << e.what();
  }
  // One parser for every spelling: what each names.
  EXPECT_EQ(ParseDeviceName("mouse").kind, DeviceName::Kind::kMouse);
  EXPECT_EQ(ParseDeviceName("scripted:poke").kind, DeviceName::Kind::kScripted);
  EXPECT_EQ(ParseDeviceName("scripted:a/b.csv").file(), "a/b.csv");
  EXPECT_EQ(ParseDeviceName("replay:r.rec").file(), "r.rec");
  EXPECT_EQ(ParseDeviceName("student:careful").what, "careful");
  EXPECT_TRUE(ParseDeviceName("student:careful").file().empty());
  EXPECT_THROW(ParseDeviceName("student:"), std::invalid_argument);
  EXPECT_THROW(MakeDevice("student:careful", *scene, 1), std::invalid_argument);
  EXPECT_THROW(MakeDevice("scripted:wiggle", *scene, 1), std::invalid_argument);
  EXPECT_THROW(MakeDevice("replay:" + Out("none.rec").string(), *scene, 1),
               RecordingError);
}

// The soft gingiva object comes first in the file, a hard one after it, each
// with its own tree settings: after compiling, each has its own tree.
TEST(CompileScene, SoftObjectsMovedLastKeepTheirOwnTreeSettings) {
  const fs::path scene = Out("order.yaml");
  std::ofstream(scene) << "effects: [contact, gingiva_compliance]\n"
                          "objects:\n"
                          "  - name: soft\n"
                          "    cylinder: 3\n"
                          "    height_mm: 4\n"
                          "    tissue: gingiva\n"
                          "    spheretree: {levels: 2, leaves: 8}\n"
                          "  - name: hard\n"
                          "    box: [6, 6, 2]\n"
                          "    at: [20, 0, 0]\n"
                          "    tissue: bone\n"
                          "    spheretree: {levels: 3, leaves: 64}\n";
  const SceneSpec spec = LoadSceneSpec(scene);
  EXPECT_EQ(spec.objects[0].file_index, 0);
  const auto c = CompileScene(spec, Out("cache"));
  ASSERT_EQ(c->spec.objects.size(), 2u);
  EXPECT_EQ(c->spec.objects[0].name, "hard") << "hard objects first in the engine";
  EXPECT_EQ(c->spec.objects[0].file_index, 1) << "but it keeps its place in the file";
  EXPECT_EQ(c->spec.objects[1].file_index, 0);
  auto leaves = [](const SphereTree& t) {
    int n = 0;
    for (std::size_t i = 0; i < t.size(); ++i) n += t.IsLeaf(i);
    return n;
  };
  EXPECT_GT(leaves(c->trees[0]), 8) << "the hard box has its 64-leaf tree";
  EXPECT_LE(leaves(c->trees[0]), 64);
  EXPECT_LE(leaves(c->trees[1]), 8) << "the soft cylinder has its 8-leaf tree";
}

}  // namespace
}  // namespace sulcus
