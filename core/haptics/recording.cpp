#include "core/haptics/recording.h"

#include <zstd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <ostream>

#include "core/base/files.h"
#include "core/base/text.h"
#include "core/haptics/recording_codec.h"

namespace sulcus {
namespace {

constexpr char kMagic[8] = {'S', 'U', 'L', 'C', 'U', 'S', 'R', '\n'};
constexpr char kFrameMarker[4] = {'F', 'R', 'M', '1'};

// Appends plain bytes (the file is little-endian; so is every machine Sulcus runs on).
class Out {
 public:
  template <class T>
  void Put(const T& v) {
    const auto* p = reinterpret_cast<const char*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
  }
  void PutString(const std::string& s) {
    Put(static_cast<std::uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
  }
  void PutPose(const RigidTransform& X) {
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) Put(X.rotation()(r, c));
    for (int i = 0; i < 3; ++i) Put(X.translation()[i]);
  }
  void PutVector(const Vector3& v) {
    for (int i = 0; i < 3; ++i) Put(v[i]);
  }
  std::vector<char> bytes;
};

class In {
 public:
  In(const std::vector<char>& data, const std::filesystem::path& file)
      : data_(data), file_(file) {}
  template <class T>
  bool Get(T* v) {
    if (pos_ + sizeof(T) > data_.size()) return false;
    std::memcpy(v, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return true;
  }
  bool GetString(std::string* s) {
    std::uint32_t n = 0;
    if (!Get(&n) || pos_ + n > data_.size() || n > 4096) return false;
    s->assign(data_.data() + pos_, n);
    pos_ += n;
    return true;
  }
  bool GetPose(RigidTransform* X) {
    Matrix3 R;
    Vector3 p;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r)
        if (!Get(&R(r, c))) return false;
    if (!GetVector(&p)) return false;
    *X = RigidTransform(R, p);
    return true;
  }
  bool GetVector(Vector3* v) {
    for (int i = 0; i < 3; ++i)
      if (!Get(&(*v)[i])) return false;
    return true;
  }
  std::size_t pos() const { return pos_; }
  bool done() const { return pos_ == data_.size(); }
  [[noreturn]] void Fail(const std::string& what) const {
    throw RecordingError(file_.string() + ": byte " + std::to_string(pos_) + ": " +
                         ShortenQuoted(what));
  }

 private:
  const std::vector<char>& data_;
  const std::filesystem::path& file_;
  std::size_t pos_ = 0;
};

bool GetFrame(In* in, TickRecord* r) {
  char marker[4];
  for (char& c : marker)
    if (!in->Get(&c)) return false;
  if (std::memcmp(marker, kFrameMarker, 4) != 0)
    in->Fail("expected a frame marker 'FRM1' (corrupt recording)");
  std::uint8_t fresh = 0, overrun = 0, events = 0;
  if (!in->Get(&r->tick) || !in->Get(&r->time_s) || !in->Get(&r->sample.time_s) ||
      !in->GetPose(&r->sample.X_WH) || !in->Get(&r->sample.buttons) || !in->Get(&fresh) ||
      !in->Get(&overrun) || !in->GetPose(&r->X_WG) || !in->GetVector(&r->force_W) ||
      !in->GetVector(&r->torque_W) || !in->Get(&events) || !in->Get(&r->events_dropped))
    return false;
  if (events > TickRecord::kMaxEvents)
    in->Fail("a frame lists " + std::to_string(events) + " events, at most " +
             std::to_string(TickRecord::kMaxEvents) + " expected");
  r->fresh = fresh != 0;
  r->overrun = overrun != 0;
  r->sample.as_given = true;  // format 2 kept readings off the grid: used exactly
  r->num_events = events;
  for (int i = 0; i < events; ++i) {
    HapticEvent& e = r->events[i];
    std::uint8_t kind = 0;
    if (!in->Get(&kind) || !in->Get(&e.object) || !in->Get(&e.tick) ||
        !in->Get(&e.payload))
      return false;
    if (kind >= kNumEventKinds) in->Fail("unknown event kind " + std::to_string(kind));
    e.kind = static_cast<EventKind>(kind);
  }
  return true;
}

}  // namespace

RecordingWriter::RecordingWriter(const std::filesystem::path& file,
                                 const RecordingHeader& header)
    : file_(file), encoder_(std::make_unique<TickEncoder>(header.rate_hz)) {
  out_ = std::fopen(file.string().c_str(), "wb");
  if (!out_)
    throw RecordingError(file.string() +
                         ": cannot create the recording: " + std::strerror(errno));
  zstd_ = ZSTD_createCCtx();
  if (!zstd_) {
    std::fclose(out_);
    out_ = nullptr;
    throw RecordingError(file.string() + ": cannot start the compressor (out of memory)");
  }
  compressed_.resize(ZSTD_CStreamOutSize());
  ZSTD_CCtx_setParameter(zstd_, ZSTD_c_compressionLevel, 3);
  ZSTD_CCtx_setParameter(zstd_, ZSTD_c_checksumFlag, 1);
  Out o;
  for (char c : kMagic) o.Put(c);
  o.Put(kRecordingVersion);
  o.Put(header.scene_hash);
  o.Put(header.rate_hz);
  o.PutString(header.device_name);
  o.PutString(header.scene_file);
  if (std::fwrite(o.bytes.data(), 1, o.bytes.size(), out_) != o.bytes.size())
    write_failed_ = true;
  writer_ = std::thread([this] { Drain(); });
}

RecordingWriter::~RecordingWriter() {
  try {
    Finish();
  } catch (const RecordingError&) {
    // Reported by an explicit Finish(); a destructor must not throw.
  }
  if (zstd_) ZSTD_freeCCtx(zstd_);
}

// Compresses `raw` into the file. `flush` makes everything so far decodable from
// the file (each drain does, so a crash loses only the ring); `end` closes the stream.
void RecordingWriter::Compress(const std::string& raw, bool end) {
  ZSTD_inBuffer in{raw.data(), raw.size(), 0};
  const ZSTD_EndDirective mode = end ? ZSTD_e_end : ZSTD_e_flush;
  for (;;) {
    ZSTD_outBuffer out{compressed_.data(), compressed_.size(), 0};
    const std::size_t left = ZSTD_compressStream2(zstd_, &out, &in, mode);
    if (ZSTD_isError(left)) {
      write_failed_ = true;
      return;
    }
    if (out.pos > 0 && std::fwrite(compressed_.data(), 1, out.pos, out_) != out.pos)
      write_failed_ = true;
    if (left == 0 && in.pos == in.size) break;
  }
  if (std::fflush(out_) != 0) write_failed_ = true;
}

void RecordingWriter::Drain() {
  std::string raw;
  TickRecord r;
  for (;;) {
    const bool stopping = stop_.load(std::memory_order_acquire);
    raw.clear();
    std::uint64_t n = 0;
    while (ring_.Pop(&r)) {
      encoder_->Put(r, &raw);
      ++n;
    }
    if (!raw.empty() || stopping) Compress(raw, stopping);
    written_.fetch_add(n);
    if (stopping) break;  // the ring was drained after stop was seen
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void RecordingWriter::PushWaiting(const TickRecord& r) {
  while (ring_.size() >= ring_.capacity())
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ring_.Push(r);
}

void RecordingWriter::Finish() {
  if (!out_) return;
  stop_.store(true, std::memory_order_release);
  if (writer_.joinable()) writer_.join();
  const bool close_failed = std::fclose(out_) != 0;
  out_ = nullptr;
  if (write_failed_ || close_failed)
    throw RecordingError(file_.string() + ": writing the recording failed (disk full?)");
}

namespace {

// A recording is replayed into the engine and read into reports: a NaN or an
// infinity in it is corruption, refused, never carried on.
void RefuseNonFinite(const TickRecord& r, const std::filesystem::path& file,
                     std::size_t frame, const std::string& where) {
  const auto finite = [](const RigidTransform& X) {
    return X.rotation().allFinite() && X.translation().allFinite();
  };
  if (!std::isfinite(r.time_s) || !std::isfinite(r.sample.time_s) ||
      !finite(r.sample.X_WH) || !finite(r.X_WG) || !r.force_W.allFinite() ||
      !r.torque_W.allFinite())
    throw RecordingError(file.string() + ": frame " + std::to_string(frame) + " (" +
                         where +
                         ") holds a non-finite number (NaN or infinity): the recording "
                         "is corrupt");
}

void ReadFormat2(In* in, const std::filesystem::path& file, Recording* rec) {
  while (!in->done()) {
    const std::size_t at = in->pos();
    TickRecord r;
    if (!GetFrame(in, &r)) {
      rec->warning = file.string() + ": truncated after frame " +
                     std::to_string(rec->frames.size()) + " (byte " + std::to_string(at) +
                     "); the " + std::to_string(rec->frames.size()) +
                     " frames before it are kept";
      break;
    }
    RefuseNonFinite(r, file, rec->frames.size(), "byte " + std::to_string(at));
    rec->frames.push_back(r);
  }
}

// Format 3: the zstd stream after the header, decompressed as far as it goes (a
// crash leaves it unfinished: the ticks of every flushed drain are kept), then
// decoded tick by tick.
void ReadFormat3(const std::vector<char>& data, std::size_t from,
                 const std::filesystem::path& file, Recording* rec) {
  std::string raw;
  std::string cut;  // why the stream ends early, if it does
  {
    ZSTD_DCtx* z = ZSTD_createDCtx();
    if (!z) throw RecordingError(file.string() + ": out of memory for the decompressor");
    ZSTD_inBuffer in{data.data() + from, data.size() - from, 0};
    std::vector<char> chunk(ZSTD_DStreamOutSize());
    std::size_t left = 1;  // 0 once a zstd frame is complete
    for (;;) {
      ZSTD_outBuffer out{chunk.data(), chunk.size(), 0};
      left = ZSTD_decompressStream(z, &out, &in);
      if (ZSTD_isError(left)) {
        cut = std::string("its compressed data is corrupt at byte ") +
              std::to_string(from + in.pos) + " (" + ZSTD_getErrorName(left) + ")";
        break;
      }
      raw.append(chunk.data(), out.pos);
      if (in.pos == in.size && out.pos < out.size) break;  // all read, all flushed
    }
    ZSTD_freeDCtx(z);
    if (cut.empty() && left != 0)
      cut = "its compressed stream ends early (the recording was not finished)";
  }
  TickDecoder decoder(rec->header.rate_hz);
  const char* at = raw.data();
  const char* end = raw.data() + raw.size();
  for (;;) {
    TickRecord r;
    std::string why;
    const std::size_t offset = static_cast<std::size_t>(at - raw.data());
    const TickDecoder::Result got = decoder.Get(&at, end, &r, &why);
    if (got == TickDecoder::Result::kEnd) break;
    if (got == TickDecoder::Result::kCorrupt)
      throw RecordingError(
          file.string() + ": tick " + std::to_string(rec->frames.size()) + " (byte " +
          std::to_string(offset) + " of the decompressed ticks): " + why +
          " (corrupt recording)");
    if (got == TickDecoder::Result::kTruncated) {
      if (cut.empty()) cut = "it ends inside a tick";
      break;
    }
    RefuseNonFinite(r, file, rec->frames.size(),
                    "byte " + std::to_string(offset) + " of the decompressed ticks");
    rec->frames.push_back(r);
  }
  if (!cut.empty())
    rec->warning = file.string() + ": truncated after frame " +
                   std::to_string(rec->frames.size()) + ": " + cut + "; the " +
                   std::to_string(rec->frames.size()) + " frames before it are kept";
}

}  // namespace

Recording ReadRecording(const std::filesystem::path& file) {
  if (const std::string why = UnreadableReason(file); !why.empty())
    throw RecordingError(file.string() + ": " + why);
  std::ifstream f(file, std::ios::binary);
  if (!f) throw RecordingError(file.string() + ": cannot open the recording");
  const std::vector<char> data((std::istreambuf_iterator<char>(f)),
                               std::istreambuf_iterator<char>());
  In in(data, file);
  Recording rec;
  char magic[8];
  for (char& c : magic)
    if (!in.Get(&c)) in.Fail("too short to be a Sulcus recording");
  if (std::memcmp(magic, kMagic, 8) != 0)
    throw RecordingError(file.string() +
                         ": not a Sulcus recording (expected 'SULCUSR' at byte 0)");
  if (!in.Get(&rec.header.version)) in.Fail("truncated header");
  if (rec.header.version != kRecordingVersion && rec.header.version != 2)
    in.Fail("recording format version " + std::to_string(rec.header.version) +
            ", this build reads versions 2 and " + std::to_string(kRecordingVersion) +
            (rec.header.version < 2
                 ? " (the file is from an older Sulcus; record it again)"
                 : ""));
  if (!in.Get(&rec.header.scene_hash) || !in.Get(&rec.header.rate_hz) ||
      !in.GetString(&rec.header.device_name) || !in.GetString(&rec.header.scene_file))
    in.Fail("truncated or corrupt header");
  if (!(rec.header.rate_hz > 0 && rec.header.rate_hz <= 100000))
    in.Fail("rate " + std::to_string(rec.header.rate_hz) + " Hz is not a haptic rate");
  rec.file_bytes = data.size();
  if (rec.header.version == 2)
    ReadFormat2(&in, file, &rec);
  else
    ReadFormat3(data, in.pos(), file, &rec);
  return rec;
}

void ExportCsv(const Recording& rec, std::ostream& out) {
  out << "tick,t_s,device_t_s,fresh,overrun,buttons,"
         "h_x_mm,h_y_mm,h_z_mm,h_qw,h_qx,h_qy,h_qz,"
         "g_x_mm,g_y_mm,g_z_mm,g_qw,g_qx,g_qy,g_qz,"
         "f_x_n,f_y_n,f_z_n,t_x_nmm,t_y_nmm,t_z_nmm,events\n";
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  auto pose = [&](const RigidTransform& X) {
    const Quaternion q(X.rotation());
    out << X.translation().x() << ',' << X.translation().y() << ',' << X.translation().z()
        << ',' << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z() << ',';
  };
  for (const TickRecord& r : rec.frames) {
    out << r.tick << ',' << r.time_s << ',' << r.sample.time_s << ',' << int(r.fresh)
        << ',' << int(r.overrun) << ',' << r.sample.buttons << ',';
    pose(r.sample.X_WH);
    pose(r.X_WG);
    out << r.force_W.x() << ',' << r.force_W.y() << ',' << r.force_W.z() << ','
        << r.torque_W.x() << ',' << r.torque_W.y() << ',' << r.torque_W.z() << ',';
    for (int i = 0; i < r.num_events; ++i) {
      const HapticEvent& e = r.events[i];
      out << (i ? ";" : "") << ToString(e.kind);
      switch (e.kind) {
        case EventKind::kCommand:
          out << ':'
              << ToString(static_cast<HapticCommand::Kind>(e.payload.command.command))
              << ':' << e.payload.command.value;
          break;
        case EventKind::kForceAbove:
        case EventKind::kForceBelow:
          out << ':' << e.payload.force.force_n;
          break;
        case EventKind::kProbeReading: {
          const ReadingPayload& p = e.payload.reading;
          out << ':' << p.fdi << ':' << p.site << ':' << p.depth_mm << ':'
              << p.peak_force_n << ':' << p.axis_angle_deg;
          break;
        }
        case EventKind::kBleeding:
          out << ':' << e.payload.bleeding.fdi << ':' << e.payload.bleeding.site;
          break;
        case EventKind::kCalculusTouched:
          out << ':' << e.payload.calculus.fdi << ':' << e.payload.calculus.site << ':'
              << e.payload.calculus.force_n;
          break;
        case EventKind::kTissueDamage:
        case EventKind::kCariesCatch:
          out << ':' << e.object << ':' << e.payload.damage.force_n;
          break;
        default:
          if (e.object >= 0) out << ':' << e.object;
      }
    }
    out << '\n';
  }
}

ReplayDevice::ReplayDevice(const Recording& recording) : recording_(recording) {
  caps_.name = recording.header.device_name + " (replay)";
  caps_.input_dof = 6;
  caps_.output_dof = 0;
  caps_.max_force_n = 1e9;
  caps_.max_torque_nmm = 1e9;
}

bool ReplayDevice::Read(double, DeviceSample* out) noexcept {
  if (next_ >= recording_.frames.size()) {
    if (!recording_.frames.empty()) *out = recording_.frames.back().sample;
    return false;
  }
  const TickRecord& f = recording_.frames[next_++];
  *out = f.sample;
  return f.fresh;
}

}  // namespace sulcus
