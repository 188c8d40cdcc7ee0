#include "core/haptics/recording_codec.h"

#include <cmath>
#include <cstring>

namespace sulcus {
namespace {

// Flags of a tick (first byte).
constexpr std::uint8_t kFresh = 1 << 0;
constexpr std::uint8_t kOverrun = 1 << 1;
constexpr std::uint8_t kTickJump = 1 << 2;    // zigzag varint: tick - (previous + 1)
constexpr std::uint8_t kOwnTime = 1 << 3;     // f64: time_s is not tick / rate
constexpr std::uint8_t kSampleTime = 3 << 4;  // 2 bits, kSampleTime* below
constexpr std::uint8_t kButtons = 1 << 6;     // varint: the buttons changed
constexpr std::uint8_t kMore = 1 << 7;        // a second flags byte follows
// The device's time stamp.
constexpr int kSampleTimeIsTickTime = 0, kSampleTimeZero = 1, kSampleTimeRaw = 2,
              kSampleTimeSame = 3;
// Second flags byte.
constexpr std::uint8_t kEvents = 1 << 0;      // u8 count, then the events
constexpr std::uint8_t kDropped = 1 << 1;     // varint: events beyond the 16 kept
constexpr std::uint8_t kRawSample = 1 << 2;   // 12 f64: the reading is off the grid
constexpr std::uint8_t kRawGraphic = 1 << 3;  // 12 f64: the rendered pose is off it
constexpr std::uint8_t kRawWrench = 1 << 4;   // 6 f64: force and torque off theirs
constexpr std::uint8_t kAsGiven = 1 << 5;     // the raw reading is used as given

// Channels: 0-6 the reading's code, 7-13 the rendered pose's, 14-16 force,
// 17-19 torque.
constexpr int kSampleChannel = 0, kGraphicChannel = 7, kForceChannel = 14,
              kTorqueChannel = 17;

std::uint64_t ZigZag(std::int64_t v) {
  return (static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63);
}
std::int64_t UnZigZag(std::uint64_t u) {
  return static_cast<std::int64_t>((u >> 1) ^ (~(u & 1) + 1));
}

void PutVarint(std::uint64_t v, std::string* out) {
  while (v >= 0x80) {
    out->push_back(static_cast<char>((v & 0x7f) | 0x80));
    v >>= 7;
  }
  out->push_back(static_cast<char>(v));
}
template <class T>
void PutRaw(const T& v, std::string* out) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}
void PutRawPose(const RigidTransform& X, std::string* out) {
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) PutRaw(X.rotation()(r, c), out);
  for (int i = 0; i < 3; ++i) PutRaw(X.translation()[i], out);
}

// Reads from a byte range; every Get fails (false) past its end.
struct Reader {
  const char* at;
  const char* end;
  bool Varint(std::uint64_t* v) {
    *v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (at == end) return false;
      const auto b = static_cast<std::uint8_t>(*at++);
      *v |= static_cast<std::uint64_t>(b & 0x7f) << shift;
      if (!(b & 0x80)) return true;
    }
    overlong = true;
    return false;
  }
  template <class T>
  bool Raw(T* v) {
    if (end - at < static_cast<std::ptrdiff_t>(sizeof(T))) return false;
    std::memcpy(v, at, sizeof(T));
    at += sizeof(T);
    return true;
  }
  bool RawPose(RigidTransform* X) {
    Matrix3 R;
    Vector3 p;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r)
        if (!Raw(&R(r, c))) return false;
    for (int i = 0; i < 3; ++i)
      if (!Raw(&p[i])) return false;
    *X = RigidTransform(R, p);
    return true;
  }
  bool overlong = false;
};

// In unsigned arithmetic, which wraps: a corrupt file cannot overflow a signed sum.
std::uint64_t Predict(const std::array<std::int64_t, 2>& h) {
  return 2 * static_cast<std::uint64_t>(h[1]) - static_cast<std::uint64_t>(h[0]);
}
void Push(std::array<std::int64_t, 2>* h, std::int64_t v) {
  (*h)[0] = (*h)[1];
  (*h)[1] = v;
}

bool OnGrid(const Vector3& v, double step, std::array<std::int64_t, 3>* code) {
  if (!v.allFinite() || v.cwiseAbs().maxCoeff() > 1e9) return false;
  for (int i = 0; i < 3; ++i) (*code)[i] = std::llround(v[i] / step);
  return true;
}

}  // namespace

void TickEncoder::Put(const TickRecord& r, std::string* out) {
  std::uint8_t flags = 0, more = 0;
  if (r.fresh) flags |= kFresh;
  if (r.overrun) flags |= kOverrun;
  const std::uint64_t expected = at_.first ? 0 : at_.tick + 1;
  if (r.tick != expected) flags |= kTickJump;
  const bool own_time = r.time_s != static_cast<double>(r.tick) / at_.rate_hz;
  if (own_time) flags |= kOwnTime;
  int sample_time = kSampleTimeRaw;
  if (r.sample.time_s == r.time_s)
    sample_time = kSampleTimeIsTickTime;
  else if (r.sample.time_s == 0)
    sample_time = kSampleTimeZero;
  else if (!at_.first && r.sample.time_s == at_.sample_time_s)
    sample_time = kSampleTimeSame;
  flags |= static_cast<std::uint8_t>(sample_time << 4);
  if (r.sample.buttons != at_.buttons) flags |= kButtons;

  PoseCode graphic;
  std::array<std::int64_t, 3> force{}, torque{};
  if (r.num_events > 0) more |= kEvents;
  if (r.events_dropped > 0) more |= kDropped;
  if (!r.sample.coded) more |= kRawSample | (r.sample.as_given ? kAsGiven : 0);
  if (!EncodePose(r.X_WG, &graphic)) more |= kRawGraphic;
  if (!OnGrid(r.force_W, kForceStepN, &force) ||
      !OnGrid(r.torque_W, kTorqueStepNmm, &torque))
    more |= kRawWrench;
  if (more) flags |= kMore;

  out->push_back(static_cast<char>(flags));
  if (more) out->push_back(static_cast<char>(more));
  if (flags & kTickJump)
    PutVarint(ZigZag(static_cast<std::int64_t>(r.tick - expected)), out);
  if (own_time) PutRaw(r.time_s, out);
  if (sample_time == kSampleTimeRaw) PutRaw(r.sample.time_s, out);
  if (flags & kButtons) PutVarint(r.sample.buttons, out);
  if (more & kDropped) PutVarint(r.events_dropped, out);
  if (more & kEvents) {
    out->push_back(static_cast<char>(r.num_events));
    for (int i = 0; i < r.num_events; ++i) {
      const HapticEvent& e = r.events[i];
      out->push_back(static_cast<char>(e.kind));
      PutVarint(ZigZag(e.object), out);
      PutVarint(ZigZag(static_cast<std::int64_t>(e.tick - r.tick)), out);
      PutRaw(e.payload, out);  // fixed size: the payload of the kind, the rest zero
    }
  }
  auto channel = [&](int c, std::int64_t v) {
    PutVarint(ZigZag(static_cast<std::int64_t>(static_cast<std::uint64_t>(v) -
                                               Predict(at_.history[c]))),
              out);
    Push(&at_.history[c], v);
  };
  if (more & kRawSample) {
    PutRawPose(r.sample.X_WH, out);
  } else {
    for (int i = 0; i < 3; ++i) channel(kSampleChannel + i, r.sample.code.p[i]);
    for (int i = 0; i < 4; ++i) channel(kSampleChannel + 3 + i, r.sample.code.q[i]);
  }
  if (more & kRawGraphic) {
    PutRawPose(r.X_WG, out);
  } else {
    for (int i = 0; i < 3; ++i) channel(kGraphicChannel + i, graphic.p[i]);
    for (int i = 0; i < 4; ++i) channel(kGraphicChannel + 3 + i, graphic.q[i]);
  }
  if (more & kRawWrench) {
    for (int i = 0; i < 3; ++i) PutRaw(r.force_W[i], out);
    for (int i = 0; i < 3; ++i) PutRaw(r.torque_W[i], out);
  } else {
    for (int i = 0; i < 3; ++i) channel(kForceChannel + i, force[i]);
    for (int i = 0; i < 3; ++i) channel(kTorqueChannel + i, torque[i]);
  }
  at_.Advance(r);
}

TickDecoder::Result TickDecoder::Get(const char** at, const char* end, TickRecord* r,
                                     std::string* why) {
  if (*at == end) return Result::kEnd;
  Reader in{*at, end};
  std::uint8_t flags = 0, more = 0;
  if (!in.Raw(&flags)) return Result::kTruncated;
  if ((flags & kMore) && !in.Raw(&more)) return Result::kTruncated;
  if (more & 0xc0) {
    *why = "unknown tick flags " + std::to_string(more);
    return Result::kCorrupt;
  }
  // The record as a whole is reset: events and raw fields are read below.
  *r = TickRecord{};
  r->fresh = flags & kFresh;
  r->overrun = flags & kOverrun;
  const std::uint64_t expected = at_.first ? 0 : at_.tick + 1;
  r->tick = expected;
  std::uint64_t u = 0;
  auto fail = [&] { return in.overlong ? Result::kCorrupt : Result::kTruncated; };
  if (flags & kTickJump) {
    if (!in.Varint(&u)) return fail();
    r->tick = expected + static_cast<std::uint64_t>(UnZigZag(u));
  }
  r->time_s = static_cast<double>(r->tick) / at_.rate_hz;
  if ((flags & kOwnTime) && !in.Raw(&r->time_s)) return Result::kTruncated;
  switch ((flags & kSampleTime) >> 4) {
    case kSampleTimeIsTickTime:
      r->sample.time_s = r->time_s;
      break;
    case kSampleTimeZero:
      r->sample.time_s = 0;
      break;
    case kSampleTimeSame:
      r->sample.time_s = at_.sample_time_s;
      break;
    default:
      if (!in.Raw(&r->sample.time_s)) return Result::kTruncated;
  }
  r->sample.buttons = at_.buttons;
  if (flags & kButtons) {
    if (!in.Varint(&u)) return fail();
    r->sample.buttons = static_cast<std::uint32_t>(u);
  }
  if (more & kDropped) {
    if (!in.Varint(&u)) return fail();
    r->events_dropped = static_cast<std::uint32_t>(u);
  }
  if (more & kEvents) {
    std::uint8_t n = 0;
    if (!in.Raw(&n)) return Result::kTruncated;
    if (n > TickRecord::kMaxEvents) {
      *why = "a tick lists " + std::to_string(n) + " events, at most " +
             std::to_string(TickRecord::kMaxEvents) + " expected";
      return Result::kCorrupt;
    }
    r->num_events = n;
    for (int i = 0; i < n; ++i) {
      HapticEvent& e = r->events[i];
      std::uint8_t kind = 0;
      std::uint64_t object = 0, dt = 0;
      if (!in.Raw(&kind) || !in.Varint(&object) || !in.Varint(&dt) || !in.Raw(&e.payload))
        return fail();
      if (kind >= kNumEventKinds) {
        *why = "unknown event kind " + std::to_string(kind);
        return Result::kCorrupt;
      }
      e.kind = static_cast<EventKind>(kind);
      e.object = static_cast<std::int32_t>(UnZigZag(object));
      e.tick = r->tick + static_cast<std::uint64_t>(UnZigZag(dt));
    }
  }
  // The channels advance only when the whole tick was read: a copy of the history.
  auto history = at_.history;
  auto channel = [&](int c, std::int64_t* v) {
    if (!in.Varint(&u)) return false;
    *v = static_cast<std::int64_t>(Predict(history[c]) +
                                   static_cast<std::uint64_t>(UnZigZag(u)));
    Push(&history[c], *v);
    return true;
  };
  if (more & kRawSample) {
    if (!in.RawPose(&r->sample.X_WH)) return fail();
    r->sample.as_given = (more & kAsGiven) != 0;
  } else {
    PoseCode& c = r->sample.code;
    for (int i = 0; i < 3; ++i)
      if (!channel(kSampleChannel + i, &c.p[i])) return fail();
    for (int i = 0; i < 4; ++i)
      if (!channel(kSampleChannel + 3 + i, &c.q[i])) return fail();
    r->sample.X_WH = DecodePose(c);
    r->sample.coded = true;
  }
  if (more & kRawGraphic) {
    if (!in.RawPose(&r->X_WG)) return fail();
  } else {
    PoseCode c;
    for (int i = 0; i < 3; ++i)
      if (!channel(kGraphicChannel + i, &c.p[i])) return fail();
    for (int i = 0; i < 4; ++i)
      if (!channel(kGraphicChannel + 3 + i, &c.q[i])) return fail();
    r->X_WG = DecodePose(c);
  }
  if (more & kRawWrench) {
    for (int i = 0; i < 3; ++i)
      if (!in.Raw(&r->force_W[i])) return Result::kTruncated;
    for (int i = 0; i < 3; ++i)
      if (!in.Raw(&r->torque_W[i])) return Result::kTruncated;
  } else {
    std::int64_t v = 0;
    for (int i = 0; i < 3; ++i) {
      if (!channel(kForceChannel + i, &v)) return fail();
      r->force_W[i] = static_cast<double>(v) * kForceStepN;
    }
    for (int i = 0; i < 3; ++i) {
      if (!channel(kTorqueChannel + i, &v)) return fail();
      r->torque_W[i] = static_cast<double>(v) * kTorqueStepNmm;
    }
  }
  at_.history = history;
  at_.Advance(*r);
  *at = in.at;
  return Result::kTick;
}

}  // namespace sulcus
