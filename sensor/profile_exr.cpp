#include "sensor/profile_exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <IlmThreadPool.h>
#include <ImfThreading.h>
#include <ImfHeader.h>
#include <iterator>
#include <vector>
#include <ImfInputPart.h>
#include <ImfMultiPartInputFile.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfCompression.h>
#include <ImfStdIO.h>
#include <openexr.h>
#include <ImfStringAttribute.h>
#include <unistd.h>
#include <zlib.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>

#include "common/parallel.h"
#include "sensor/pose.h"

namespace vts {
namespace fs = std::filesystem;
namespace {

// Version 2 (written): two parts, "profiles" (per point) and "rows" (per
// row), no subsampled channels. Version 1 (read): one part whose per-row
// channels are x-subsampled (xSampling = width), which OpenImageIO refuses.
constexpr const char* kFormat = "vts-profiles 2";
constexpr const char* kFormatV1 = "vts-profiles 1";
constexpr const char* kProfilesPart = "profiles";
constexpr const char* kRowsPart = "rows";
constexpr const char* kUnits = "mm (y, z, range, pose.t*), s (time)";
constexpr const char* kFrame =
    "Sensor frame: origin at the laser, z along the optical axis (range), y along the laser "
    "line, x = y cross z (the travel direction). Row pose (pose.t*, pose.q*) is "
    "world_from_sensor: p_world = R(q) * p_sensor + t.";
constexpr const char* kColumns =
    "Row r is profile r in scan order. Column i of N = vts.scanner.points samples the "
    "sensor-frame ray (0, t_i, 1) with t_i = tan(fan_deg / 2) * (2 * (i + 0.5) / N - 1). "
    "Invalid points have range = y = z = 0 and valid = 0.";
constexpr const char* kRowsText =
    "Row r holds the pose (world_from_sensor) and time of row r of part 'profiles'. pose.* and "
    "time are rounded to float; f64hi.<name> and f64lo.<name> hold the high and low 32 bits of "
    "the exact IEEE binary64 value.";
constexpr const char* kReferenceKind = "embree3-robust";
constexpr const char* kNoReference = "none";

// Rows moved per OpenEXR call; memory is this many rows whatever the file size.
constexpr int kChunkRows = 256;

// Per-point channels: full resolution, FLOAT. Order matches Impl buffers.
// Slots 0-3: main; 4-7: reference (with has_reference); 8-11: error model
// outputs (with error_model).
constexpr int kPointSlots = 12;
constexpr std::array<const char*, kPointSlots> kPointNames = {
    "range",     "y",     "z",     "valid",  "ref.range", "ref.y",
    "ref.z",     "ref.valid", "intensity", "true.y", "true.z", "true.valid"};
constexpr const char* kModelOn = "triangulation";
constexpr const char* kModelOff = "ideal";

// The point slots a file with this info holds.
std::vector<int> point_slots(const ProfileFileInfo& info) {
  std::vector<int> slots = {0, 1, 2, 3};
  if (info.has_reference) slots.insert(slots.end(), {4, 5, 6, 7});
  if (info.error_model) slots.insert(slots.end(), {8, 9, 10, 11});
  return slots;
}
// Per-row channels: one sample per row, in part "rows" (version 1: in the
// one part, xSampling = width).
constexpr std::array<const char*, 8> kRowNames = {"pose.tx", "pose.ty", "pose.tz", "pose.qw",
                                                  "pose.qx", "pose.qy", "pose.qz", "time"};
// The per-row values are doubles; FLOAT channels hold them rounded, UINT
// channels f64hi.<name> / f64lo.<name> hold the binary64 bits for an exact
// round trip.
constexpr const char* kHiPrefix = "f64hi.";
constexpr const char* kLoPrefix = "f64lo.";

// Scanner fields added with the error model: written always, optional on
// reading (files from before it get the ScannerDesc defaults).
struct NumberField {
  const char* attribute;
  double ScannerDesc::*member;
};
struct IntField {
  const char* attribute;
  int ScannerDesc::*member;
};
const std::vector<NumberField>& number_fields() {
  static const std::vector<NumberField> fields = {
      {"vts.scanner.max_incidence_deg", &ScannerDesc::max_incidence_deg},
      {"vts.scanner.baseline_mm", &ScannerDesc::baseline_mm},
      {"vts.scanner.triangulation_deg", &ScannerDesc::triangulation_deg},
      {"vts.scanner.focal_length_mm", &ScannerDesc::focal_length_mm},
      {"vts.scanner.pixel_pitch_um", &ScannerDesc::pixel_pitch_um},
      {"vts.scanner.subpixel_step_px", &ScannerDesc::subpixel_step_px},
      {"vts.scanner.intensity_ref_range_mm", &ScannerDesc::intensity_ref_range_mm},
      {"vts.scanner.speckle_px", &ScannerDesc::speckle_px},
      {"vts.scanner.reflectivity", &ScannerDesc::reflectivity},
      {"vts.scanner.shiny_cluster_prob", &ScannerDesc::shiny_cluster_prob},
      {"vts.scanner.shiny_offset_min_mm", &ScannerDesc::shiny_offset_min_mm},
      {"vts.scanner.shiny_offset_max_mm", &ScannerDesc::shiny_offset_max_mm},
      {"vts.scanner.rough_outlier_prob", &ScannerDesc::rough_outlier_prob},
      {"vts.scanner.rough_offset_min_mm", &ScannerDesc::rough_offset_min_mm},
      {"vts.scanner.rough_offset_max_mm", &ScannerDesc::rough_offset_max_mm},
      {"vts.scanner.dropout_prob_normal", &ScannerDesc::dropout_prob_normal},
      {"vts.scanner.dropout_prob_grazing", &ScannerDesc::dropout_prob_grazing},
      // The camera image's (added with it; docs/SENSOR_MODEL.md "The camera image").
      {"vts.scanner.scheimpflug_deg", &ScannerDesc::scheimpflug_deg},
      {"vts.scanner.f_number", &ScannerDesc::f_number},
      {"vts.scanner.wavelength_nm", &ScannerDesc::wavelength_nm},
      {"vts.scanner.psf_sigma_px", &ScannerDesc::psf_sigma_px},
      {"vts.scanner.laser_power_mw", &ScannerDesc::laser_power_mw},
      {"vts.scanner.sheet_waist_mm", &ScannerDesc::sheet_waist_mm},
      {"vts.scanner.sheet_focus_mm", &ScannerDesc::sheet_focus_mm},
      {"vts.scanner.sheet_m2", &ScannerDesc::sheet_m2},
      {"vts.scanner.exposure_us", &ScannerDesc::exposure_us},
      {"vts.scanner.gain", &ScannerDesc::gain},
      {"vts.scanner.quantum_efficiency", &ScannerDesc::quantum_efficiency},
      {"vts.scanner.full_well_e", &ScannerDesc::full_well_e},
      {"vts.scanner.read_noise_e", &ScannerDesc::read_noise_e},
      {"vts.scanner.dark_offset_dn", &ScannerDesc::dark_offset_dn},
      {"vts.scanner.ambient_w_m2", &ScannerDesc::ambient_w_m2},
      {"vts.scanner.specular_reflectance", &ScannerDesc::specular_reflectance},
      {"vts.scanner.specular_lobe_deg", &ScannerDesc::specular_lobe_deg},
      {"vts.scanner.speckle_contrast", &ScannerDesc::speckle_contrast},
      {"vts.scanner.peak_threshold_dn", &ScannerDesc::peak_threshold_dn},
  };
  return fields;
}
const std::vector<IntField>& int_fields() {
  static const std::vector<IntField> fields = {
      {"vts.scanner.roi_first_column", &ScannerDesc::roi_first_column},
      {"vts.scanner.roi_last_column", &ScannerDesc::roi_last_column},
      {"vts.scanner.image_width_px", &ScannerDesc::image_width_px},
      {"vts.scanner.image_height_px", &ScannerDesc::image_height_px},
      {"vts.scanner.shiny_cluster_max_points", &ScannerDesc::shiny_cluster_max_points},
      {"vts.scanner.image_bits", &ScannerDesc::image_bits},
      {"vts.scanner.image_roi_first_row", &ScannerDesc::image_roi_first_row},
      {"vts.scanner.image_roi_rows", &ScannerDesc::image_roi_rows},
      {"vts.scanner.peak_window_px", &ScannerDesc::peak_window_px},
  };
  return fields;
}

std::string where(const fs::path& path) { return "profile EXR '" + path.string() + "'"; }

std::string format_double(double v) {
  char buf[64];
  // Shortest representation that reads back to the same double.
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

std::string matrix_text(const Pose& pose) {
  std::string s;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      if (!s.empty()) s += ' ';
      s += format_double(pose.matrix()(r, c));
    }
  return s;
}

}  // namespace

std::array<double, 8> profile_row_values(const Profile& p) {
  const Eigen::Quaterniond q = rotation_quat(p.world_from_sensor);
  const Vec3 t = p.world_from_sensor.translation();
  return {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z(), p.time_s};
}

std::array<double, 8> recording_row_values(const ProfileRecording& rec, std::size_t r) {
  return r < rec.row_values.size() ? rec.row_values[r] : profile_row_values(rec.profiles.at(r));
}

std::vector<std::pair<std::string, std::string>> profile_attributes(const ProfileFileInfo& info) {
  std::vector<std::pair<std::string, std::string>> a;
  auto put = [&](const char* name, const std::string& value) { a.emplace_back(name, value); };
  const ScannerDesc& s = info.scanner;
  put("vts.units", kUnits);
  put("vts.frame", kFrame);
  put("vts.columns", kColumns);
  put("vts.scanner.name", s.name);
  put("vts.scanner.fan_deg", format_double(s.fan_deg));
  put("vts.scanner.points", std::to_string(s.points));
  put("vts.scanner.min_range_mm", format_double(s.min_range_mm));
  put("vts.scanner.max_range_mm", format_double(s.max_range_mm));
  put("vts.scanner.max_hit_mm", format_double(s.max_hit_mm));
  put("vts.scanner.rate_hz", format_double(s.rate_hz));
  put("vts.scanner.tool_from_laser", matrix_text(s.tool_from_laser));
  for (const NumberField& f : number_fields()) put(f.attribute, format_double(s.*f.member));
  for (const IntField& f : int_fields()) put(f.attribute, std::to_string(s.*f.member));
  put("vts.scanner.material", s.material);
  put("vts.scanner.peak_method", s.peak_method);
  put("vts.scanner.peak_policy", s.peak_policy);
  put("vts.scanner.image_noise", s.image_noise ? "true" : "false");
  put("vts.scanner.camera_image", s.camera_image ? "true" : "false");
  put("vts.error_model", info.error_model ? kModelOn : kModelOff);
  put("vts.scene.name", info.scene_name);
  put("vts.scene.yaml", info.scene_text);
  put("vts.reference", info.has_reference ? kReferenceKind : kNoReference);
  put("vts.seed", std::to_string(info.seed));
  return a;
}

namespace {

struct CompressionName {
  ExrCompression method;
  std::string_view name;
  Imf::Compression exr;
};
constexpr std::array<CompressionName, 5> kCompressions = {{
    {ExrCompression::Zip, "zip", Imf::ZIP_COMPRESSION},
    {ExrCompression::Zips, "zips", Imf::ZIPS_COMPRESSION},
    {ExrCompression::Piz, "piz", Imf::PIZ_COMPRESSION},
    {ExrCompression::Rle, "rle", Imf::RLE_COMPRESSION},
    {ExrCompression::None, "none", Imf::NO_COMPRESSION},
}};

const CompressionName& compression_entry(ExrCompression c) {
  for (const CompressionName& e : kCompressions)
    if (e.method == c) return e;
  throw std::invalid_argument("unknown ExrCompression");
}

}  // namespace

std::string_view to_string(ExrCompression compression) { return compression_entry(compression).name; }

std::optional<ExrCompression> exr_compression_from_string(std::string_view name) {
  for (const CompressionName& e : kCompressions)
    if (e.name == name) return e.method;
  return std::nullopt;
}

std::vector<std::string> exr_compression_names() {
  std::vector<std::string> names;
  for (const CompressionName& e : kCompressions) names.emplace_back(e.name);
  return names;
}

namespace {

// OpenEXR's thread pool on the vts threads (common/parallel.h): each task
// OpenEXR adds is queued and a thread of the arena takes it. OpenEXR's writer
// blocks its caller until its tasks are done, so when it adds a task while
// more wait than the arena's other threads can start, the caller takes the
// oldest itself: the other threads and the caller compress together, as
// many as the thread limit. A caller that is itself in a parallel loop
// takes every task (its waiting must not depend on the arena's threads it
// may be holding).
// Set while a writer that wants no threads (an uncompressed file) hands
// rows to OpenEXR: its tasks then run on the calling thread, as with
// OpenEXR's own pool of 0 threads. OpenEXR passes every row through the
// global pool whatever thread count a file was opened with.
thread_local bool t_tasks_inline = false;

class ArenaTaskProvider final : public IlmThread::ThreadPoolProvider {
 public:
  explicit ArenaTaskProvider(int threads) : threads_(threads) {}
  ~ArenaTaskProvider() override { finish(); }

  int numThreads() const override { return threads_; }
  void setNumThreads(int) override {}  // the thread limit decides
  void addTask(IlmThread::Task* task) override {
    if (thread_slot() >= 0 || t_tasks_inline) {
      run(task);
      return;
    }
    std::size_t waiting = 0;
    {
      std::lock_guard lock(queue_->mutex);
      queue_->tasks.push_back(task);
      waiting = queue_->tasks.size();
    }
    // The queue, not the provider, goes with the detached task: OpenEXR may
    // replace the provider while a finished queue's last takers are pending.
    run_detached([queue = queue_] { queue->run_one(); });
    if (waiting >= static_cast<std::size_t>(threads_)) queue_->run_one();
  }
  void finish() override {
    while (queue_->run_one()) {
    }
    std::unique_lock lock(queue_->mutex);
    queue_->idle.wait(lock, [&] { return queue_->running == 0; });
  }

 private:
  // As OpenEXR's own provider does: the task goes before its group hears
  // that it is done.
  static void run(IlmThread::Task* task) {
    IlmThread::TaskGroup* group = task->group();
    task->execute();
    delete task;
    if (group) group->finishOneTask();
  }
  struct Queue {
    std::mutex mutex;
    std::condition_variable idle;
    std::deque<IlmThread::Task*> tasks;
    int running = 0;
    // Runs the oldest task, if any; false when there was none.
    bool run_one() {
      IlmThread::Task* task = nullptr;
      {
        std::lock_guard lock(mutex);
        if (tasks.empty()) return false;
        task = tasks.front();
        tasks.pop_front();
        ++running;
      }
      run(task);
      {
        std::lock_guard lock(mutex);
        --running;
      }
      idle.notify_all();
      return true;
    }
  };
  int threads_;
  std::shared_ptr<Queue> queue_ = std::make_shared<Queue>();
};

// The threads OpenEXR compresses a file with: the thread limit on the vts
// arena (the provider set once), or 0, the caller alone, for a limit of 1.
int exr_threads() {
  static const int threads = [] {
    const int n = thread_limit();
    if (n > 1) IlmThread::ThreadPool::globalThreadPool().setThreadProvider(new ArenaTaskProvider(n));
    return n > 1 ? n : 0;
  }();
  return threads;
}

}  // namespace

struct ProfileExrWriter::Impl {
  fs::path path;
  fs::path tmp;
  ProfileFileInfo info;
  ExrCompression compression = ExrCompression::Zip;
  int width = 0;
  int rows_written = 0;  // rows handed to write()
  int chunk_first = 0;   // row of chunk slot 0
  int chunk_rows = 0;    // rows buffered, not yet given to OpenEXR
  bool finished = false;
  bool failed = false;

  std::ofstream ofs;
  std::unique_ptr<Imf::StdOFStream> stream;
  std::unique_ptr<Imf::MultiPartOutputFile> file;
  std::unique_ptr<Imf::OutputPart> profiles_part, rows_part;

  std::array<std::vector<float>, kPointSlots> points;  // see kPointNames
  std::array<std::vector<float>, 8> row_f;
  std::array<std::vector<std::uint32_t>, 8> row_hi, row_lo;

  std::string err(const std::string& what) const { return where(path) + ": " + what; }

  void open();
  void flush();
  // Closes and deletes the temporary file; never throws.
  void discard() noexcept;
};

void ProfileExrWriter::Impl::open() {
  if (const std::string why = validate(info.scanner); !why.empty())
    throw ExrError(err("scanner " + why));
  if (info.profiles < 1)
    throw ExrError(err("profiles = " + std::to_string(info.profiles) +
                       ": a file needs at least one row"));
  width = info.scanner.points;

  std::error_code ec;
  if (fs::is_directory(path, ec)) throw ExrError(err("is a directory"));
  const fs::path dir = path.parent_path();
  if (!dir.empty()) {
    fs::create_directories(dir, ec);
    if (ec) throw ExrError(err("cannot create directory '" + dir.string() + "': " + ec.message()));
  }
  tmp = path;
  tmp += ".tmp-" + std::to_string(::getpid());

  // Part 0, "profiles": one row per profile, one column per point. Part 1,
  // "rows": one row per profile, one column. Both compressed alike; ZIP and
  // ZIPS with zlib's fastest level: about a third of level 4's time for files
  // a few per cent larger (docs/PERFORMANCE.md); compression bounds vts scan.
  const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(width - 1, info.profiles - 1));
  auto part_header = [&](const char* name, int part_width) {
    Imf::Header h(display, Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(part_width - 1, info.profiles - 1)));
    h.setName(name);
    h.setType(Imf::SCANLINEIMAGE);
    h.compression() = compression_entry(compression).exr;
    h.zipCompressionLevel() = 1;
    h.lineOrder() = Imf::INCREASING_Y;
    h.insert("vts.format", Imf::StringAttribute(kFormat));
    return h;
  };
  std::array<Imf::Header, 2> headers = {part_header(kProfilesPart, width), part_header(kRowsPart, 1)};
  Imf::Header& h = headers[0];
  for (int c : point_slots(info)) h.channels().insert(kPointNames[c], Imf::Channel(Imf::FLOAT));
  h.insert("comments", Imf::StringAttribute("vts laser profiles: one row per profile, one column per "
                                            "point; part 'rows': each row's pose and time (docs/EXR_FORMAT.md)"));
  for (const auto& [name, value] : profile_attributes(info)) h.insert(name, Imf::StringAttribute(value));
  Imf::Header& rh = headers[1];
  for (const char* name : kRowNames) {
    rh.channels().insert(name, Imf::Channel(Imf::FLOAT));
    rh.channels().insert(std::string(kHiPrefix) + name, Imf::Channel(Imf::UINT));
    rh.channels().insert(std::string(kLoPrefix) + name, Imf::Channel(Imf::UINT));
  }
  rh.insert("vts.rows", Imf::StringAttribute(kRowsText));

  for (int c : point_slots(info)) points[c].assign(std::size_t(kChunkRows) * width, 0.0f);
  for (int c = 0; c < 8; ++c) {
    row_f[c].assign(kChunkRows, 0.0f);
    row_hi[c].assign(kChunkRows, 0u);
    row_lo[c].assign(kChunkRows, 0u);
  }

  ofs.open(tmp, std::ios::binary | std::ios::trunc);
  if (!ofs)
    throw ExrError(err("cannot create '" + tmp.string() + "': " + std::strerror(errno)));
  try {
    stream = std::make_unique<Imf::StdOFStream>(ofs, tmp.c_str());
    // Compression (ZIP: zlib) is the writer's cost: OpenEXR compresses the
    // blocks of a chunk (16 rows for ZIP) on its thread pool, which runs on the vts
    // threads (see ArenaTaskProvider). The bytes written do not depend on
    // the thread count.
    file = std::make_unique<Imf::MultiPartOutputFile>(*stream, headers.data(), 2, false, exr_threads());
    profiles_part = std::make_unique<Imf::OutputPart>(*file, 0);
    rows_part = std::make_unique<Imf::OutputPart>(*file, 1);
  } catch (const std::exception& e) {
    discard();
    throw ExrError(err(e.what()));
  }
}

void ProfileExrWriter::Impl::flush() {
  if (chunk_rows == 0) return;
  const Imath::V2i origin(0, chunk_first);
  const std::size_t fstride = sizeof(float), ustride = sizeof(std::uint32_t);
  Imf::FrameBuffer fb, rows_fb;
  for (int c : point_slots(info))
    fb.insert(kPointNames[c],
              Imf::Slice::Make(Imf::FLOAT, points[c].data(), origin, width, kChunkRows, fstride,
                               fstride * width));
  for (int c = 0; c < 8; ++c) {
    const std::string name = kRowNames[c];
    rows_fb.insert(name, Imf::Slice::Make(Imf::FLOAT, row_f[c].data(), origin, 1, kChunkRows, fstride, fstride));
    rows_fb.insert(kHiPrefix + name,
                   Imf::Slice::Make(Imf::UINT, row_hi[c].data(), origin, 1, kChunkRows, ustride, ustride));
    rows_fb.insert(kLoPrefix + name,
                   Imf::Slice::Make(Imf::UINT, row_lo[c].data(), origin, 1, kChunkRows, ustride, ustride));
  }
  // Uncompressed, a task would only copy a row: the caller writes alone.
  struct InlineScope {
    bool saved = t_tasks_inline;
    explicit InlineScope(bool on) { t_tasks_inline = saved || on; }
    ~InlineScope() { t_tasks_inline = saved; }
  } inline_scope(compression == ExrCompression::None);
  try {
    profiles_part->setFrameBuffer(fb);
    profiles_part->writePixels(chunk_rows);
    rows_part->setFrameBuffer(rows_fb);
    rows_part->writePixels(chunk_rows);
  } catch (const std::exception& e) {
    failed = true;
    throw ExrError(err(std::string("writing rows ") + std::to_string(chunk_first) + ".." +
                       std::to_string(chunk_first + chunk_rows - 1) + ": " + e.what()));
  }
  if (!ofs) {
    failed = true;
    throw ExrError(err("write to '" + tmp.string() + "' failed"));
  }
  chunk_first += chunk_rows;
  chunk_rows = 0;
}

void ProfileExrWriter::Impl::discard() noexcept {
  try {
    profiles_part.reset();
    rows_part.reset();
    file.reset();  // OpenEXR writes its offset tables here; it swallows errors
  } catch (...) {
  }
  stream.reset();
  if (ofs.is_open()) ofs.close();
  if (!tmp.empty()) {
    std::error_code ec;
    fs::remove(tmp, ec);
  }
}

ProfileExrWriter::ProfileExrWriter(const fs::path& path, const ProfileFileInfo& info, ExrCompression compression)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->info = info;
  impl_->compression = compression;
  impl_->open();
}

ProfileExrWriter::~ProfileExrWriter() {
  if (!impl_->finished) impl_->discard();
}

void ProfileExrWriter::write(const Profile& profile, const Profile* reference) {
  Impl& m = *impl_;
  if (m.finished) throw ExrError(m.err("write() after finish()"));
  if (m.failed) throw ExrError(m.err("write() after an earlier write failed"));
  const std::string row = "row " + std::to_string(m.rows_written) + ": ";
  if (m.rows_written >= m.info.profiles)
    throw ExrError(m.err(row + "more rows than the " + std::to_string(m.info.profiles) +
                         " announced"));
  if (profile.index != m.rows_written)
    throw ExrError(m.err(row + "profile.index = " + std::to_string(profile.index) +
                         ", expected " + std::to_string(m.rows_written) +
                         " (rows must come in order)"));
  auto check_size = [&](const Profile& p, const char* what) {
    const std::size_t n = m.width;
    if (p.range_mm.size() != n || p.y_mm.size() != n || p.z_mm.size() != n || p.valid.size() != n)
      throw ExrError(m.err(row + what + " has " + std::to_string(p.range_mm.size()) +
                           " points, expected vts.scanner.points = " + std::to_string(n)));
  };
  check_size(profile, "profile");
  if (m.info.error_model) {
    const std::size_t n = m.width;
    if (profile.intensity.size() != n || profile.true_y_mm.size() != n ||
        profile.true_z_mm.size() != n || profile.true_valid.size() != n)
      throw ExrError(m.err(row + "profile has no error model output (intensity, true.*) of " +
                           std::to_string(n) + " points, but the file has those channels"));
  }
  if (m.info.has_reference && !reference)
    throw ExrError(m.err(row + "the file has reference channels but no reference was given"));
  if (!m.info.has_reference && reference)
    throw ExrError(m.err(row + "a reference was given but the file has no reference channels"));
  if (reference) check_size(*reference, "reference");

  const std::size_t off = std::size_t(m.chunk_rows) * m.width;
  auto put_points = [&](const Profile& p, int first) {
    std::copy(p.range_mm.begin(), p.range_mm.end(), m.points[first + 0].begin() + off);
    std::copy(p.y_mm.begin(), p.y_mm.end(), m.points[first + 1].begin() + off);
    std::copy(p.z_mm.begin(), p.z_mm.end(), m.points[first + 2].begin() + off);
    float* v = m.points[first + 3].data() + off;
    for (int i = 0; i < m.width; ++i) v[i] = p.valid[i] ? 1.0f : 0.0f;
  };
  put_points(profile, 0);
  if (reference) put_points(*reference, 4);
  if (m.info.error_model) {
    std::copy(profile.intensity.begin(), profile.intensity.end(), m.points[8].begin() + off);
    std::copy(profile.true_y_mm.begin(), profile.true_y_mm.end(), m.points[9].begin() + off);
    std::copy(profile.true_z_mm.begin(), profile.true_z_mm.end(), m.points[10].begin() + off);
    float* v = m.points[11].data() + off;
    for (int i = 0; i < m.width; ++i) v[i] = profile.true_valid[i] ? 1.0f : 0.0f;
  }
  const std::array<double, 8> values = profile_row_values(profile);
  for (int c = 0; c < 8; ++c) {
    const auto bits = std::bit_cast<std::uint64_t>(values[c]);
    m.row_f[c][m.chunk_rows] = static_cast<float>(values[c]);
    m.row_hi[c][m.chunk_rows] = static_cast<std::uint32_t>(bits >> 32);
    m.row_lo[c][m.chunk_rows] = static_cast<std::uint32_t>(bits);
  }
  ++m.chunk_rows;
  ++m.rows_written;
  if (m.chunk_rows == kChunkRows) m.flush();
}

void ProfileExrWriter::finish() {
  Impl& m = *impl_;
  if (m.finished) return;
  if (m.failed) {
    m.discard();
    throw ExrError(m.err("finish() after a failed write; nothing was saved"));
  }
  if (m.rows_written < m.info.profiles) {
    m.discard();
    throw ExrError(m.err("only " + std::to_string(m.rows_written) + " of " +
                         std::to_string(m.info.profiles) + " rows were written; nothing was saved"));
  }
  try {
    m.flush();
    m.profiles_part.reset();
    m.rows_part.reset();
    m.file.reset();
    m.stream.reset();
    m.ofs.flush();
    m.ofs.close();
  } catch (const std::exception& e) {
    m.discard();
    throw ExrError(m.err(std::string("closing: ") + e.what()));
  }
  if (!m.ofs) {
    m.discard();
    throw ExrError(m.err("writing '" + m.tmp.string() + "' failed"));
  }
  std::error_code ec;
  fs::rename(m.tmp, m.path, ec);
  if (ec) {
    m.discard();
    throw ExrError(m.err("cannot rename '" + m.tmp.string() + "' onto it: " + ec.message()));
  }
  m.finished = true;
}

namespace {

// OpenEXR's ZIP predictor undone in place: t[i] += t[i - 1] - 128 from i = 1
// on (a running sum of bytes, modulo 256), 16 bytes at a time.
void undo_zip_predictor(unsigned char* t, std::size_t n) {
  std::size_t i = 1;
#if defined(__SSE2__)
  const __m128i bias = _mm_set1_epi8(static_cast<char>(-128));
  for (; i + 16 <= n; i += 16) {
    __m128i v = _mm_add_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(t + i)), bias);
    v = _mm_add_epi8(v, _mm_slli_si128(v, 1));
    v = _mm_add_epi8(v, _mm_slli_si128(v, 2));
    v = _mm_add_epi8(v, _mm_slli_si128(v, 4));
    v = _mm_add_epi8(v, _mm_slli_si128(v, 8));
    v = _mm_add_epi8(v, _mm_set1_epi8(static_cast<char>(t[i - 1])));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(t + i), v);
  }
#endif
  for (; i < n; ++i) t[i] = static_cast<unsigned char>(int(t[i - 1]) + int(t[i]) - 128);
}

// OpenEXR's ZIP byte order undone: out takes bytes from the first and the
// second half of t in turn.
void deinterleave(const unsigned char* t, std::size_t n, unsigned char* out) {
  const unsigned char* t1 = t;
  const unsigned char* t2 = t + (n + 1) / 2;
  std::size_t i = 0;
#if defined(__SSE2__)
  for (; i + 32 <= n; i += 32, t1 += 16, t2 += 16) {
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(t1));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(t2));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), _mm_unpacklo_epi8(a, b));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i + 16), _mm_unpackhi_epi8(a, b));
  }
#endif
  for (; i + 1 < n; i += 2) {
    out[i] = *t1++;
    out[i + 1] = *t2++;
  }
  if (i < n) out[i] = *t1;
}

// A profile EXR open for reading: open() reads and checks the header,
// read_block() then converts up to kChunkRows rows at a time.
struct Reader {
  fs::path path;
  std::unique_ptr<Imf::MultiPartInputFile> file;
  const Imf::Header* header = nullptr;
  ProfileFileInfo info;
  int width = 0, height = 0;
  bool v1 = false;
  int row_xs = 1;                // xSampling of the per-row channels
  std::vector<int> slots;        // point_slots(info)
  std::array<bool, 8> exact{};   // per-row channel has its f64hi/f64lo bits
  std::array<std::vector<float>, kPointSlots> points;
  std::array<std::vector<float>, 8> row_f;
  std::array<std::vector<std::uint32_t>, 8> row_hi, row_lo;
  std::optional<Imf::InputPart> profiles_part, rows_part;
  // Part "profiles" decoded here rather than by OpenEXR 3.1, which copies
  // every float out of a decompressed block byte by byte (most of a read's
  // time): when it is ZIP, ZIPS or uncompressed with full-resolution
  // channels on a little-endian machine. Anything unexpected in a block
  // hands it back to OpenEXR (readPixels), so bad data gets OpenEXR's
  // message.
  struct Direct {
    bool usable = false;
    bool zip = false;
    int lines = 1;                // rows per block
    std::size_t row_bytes = 0;    // one row of every channel
    std::array<std::size_t, kPointSlots> offset{};  // of a slot's channel in a row
    // Per block of a read: its bytes as stored (OpenEXR reuses its buffer
    // from block to block), the delta-coded bytes, the decoded block. The
    // last block read stays decoded for the next read.
    struct Block {
      std::vector<unsigned char> raw, packed, data;
    };
    std::vector<Block> blocks;
    int cached = -1;  // index of the block decoded in blocks[0] at the start of a read
  } direct;

  ExrError fail(const std::string& what) const { return ExrError(where(path) + ": " + what); }

  const std::string& text(const char* name) const {
    if (const auto* a = header->findTypedAttribute<Imf::StringAttribute>(name)) return a->value();
    if (const auto it = header->find(name); it != header->end())
      throw fail(std::string("attribute ") + name + " has type " + it.attribute().typeName() +
                 ", expected string");
    throw fail(std::string("attribute ") + name + " is missing");
  }

  double number(const char* name) const {
    const std::string& s = text(name);
    double v = 0.0;
    const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
    if (res.ec != std::errc() || res.ptr != s.data() + s.size())
      throw fail(std::string("attribute ") + name + " = '" + s + "': not a number");
    return v;
  }

  template <class Int = int>
  Int integer(const char* name) const {
    const std::string& s = text(name);
    Int v = 0;
    const auto res = std::from_chars(s.data(), s.data() + s.size(), v);
    if (res.ec != std::errc() || res.ptr != s.data() + s.size())
      throw fail(std::string("attribute ") + name + " = '" + s + "': not an integer");
    return v;
  }

  bool has(const char* name) const { return header->find(name) != header->end(); }

  Pose matrix(const char* name) const {
    const std::string& s = text(name);
    std::array<double, 16> m{};
    const char* p = s.data();
    const char* end = s.data() + s.size();
    int count = 0;
    while (p < end) {
      if (*p == ' ') {
        ++p;
        continue;
      }
      double v = 0.0;
      const auto res = std::from_chars(p, end, v);
      if (res.ec != std::errc() || (res.ptr != end && *res.ptr != ' ') || count == 16)
        throw fail(std::string("attribute ") + name + " = '" + s +
                   "': expected 16 numbers (4x4 matrix, row by row)");
      m[count++] = v;
      p = res.ptr;
    }
    if (count != 16)
      throw fail(std::string("attribute ") + name + " = '" + s + "': has " +
                 std::to_string(count) + " numbers, expected 16 (4x4 matrix, row by row)");
    if (m[12] != 0.0 || m[13] != 0.0 || m[14] != 0.0 || m[15] != 1.0)
      throw fail(std::string("attribute ") + name + " = '" + s +
                 "': last row must be 0 0 0 1");
    Pose pose = Pose::Identity();
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) pose.matrix()(r, c) = m[4 * r + c];
    return pose;
  }

  // Throws unless the channel exists in `h` with this type and sampling.
  void require_channel(const Imf::Header& h, const std::string& name, Imf::PixelType type, int xs) const {
    const Imf::Channel* ch = h.channels().findChannel(name);
    if (!ch) throw fail("channel '" + name + "' is missing");
    if (ch->type != type)
      throw fail("channel '" + name + "' has pixel type " + std::to_string(int(ch->type)) +
                 ", expected " + (type == Imf::FLOAT ? "FLOAT (2)" : "UINT (0)"));
    if (ch->xSampling != xs || ch->ySampling != 1)
      throw fail("channel '" + name + "' has sampling " + std::to_string(ch->xSampling) + " " +
                 std::to_string(ch->ySampling) + ", expected " + std::to_string(xs) + " 1");
  }

  void open();
  void open_direct();
  // Rows first .. first + rows - 1 into `points` by `direct`; false when it
  // cannot (nothing to trust in `points` then).
  bool read_direct(int first, int rows);
  // Rows first .. first + rows - 1 (rows <= kChunkRows) into profiles[0 ..
  // rows - 1] and, when not null, reference[] (with has_reference) and
  // row_values[].
  void read_block(int first, int rows, Profile* profiles, Profile* reference, std::array<double, 8>* row_values);
};

void Reader::open() {
  file = std::make_unique<Imf::MultiPartInputFile>(path.c_str());
  Imf::MultiPartInputFile& in = *file;
  header = &in.header(0);

  const std::string& format = text("vts.format");
  v1 = format == kFormatV1;
  if (format != kFormat && !v1)
    throw fail("attribute vts.format = '" + format + "', expected '" + kFormat + "' (or '" +
               kFormatV1 + "')");
  ScannerDesc& s = info.scanner;
  s.name = text("vts.scanner.name");
  s.fan_deg = number("vts.scanner.fan_deg");
  s.points = integer("vts.scanner.points");
  s.min_range_mm = number("vts.scanner.min_range_mm");
  s.max_range_mm = number("vts.scanner.max_range_mm");
  s.max_hit_mm = number("vts.scanner.max_hit_mm");
  s.rate_hz = number("vts.scanner.rate_hz");
  s.tool_from_laser = matrix("vts.scanner.tool_from_laser");
  for (const NumberField& f : number_fields())
    if (has(f.attribute)) s.*f.member = number(f.attribute);
  for (const IntField& f : int_fields())
    if (has(f.attribute)) s.*f.member = integer(f.attribute);
  if (has("vts.scanner.material")) s.material = text("vts.scanner.material");
  if (has("vts.scanner.peak_method")) s.peak_method = text("vts.scanner.peak_method");
  if (has("vts.scanner.peak_policy")) s.peak_policy = text("vts.scanner.peak_policy");
  for (const auto& [attribute, member] : {std::pair{"vts.scanner.image_noise", &ScannerDesc::image_noise},
                                          std::pair{"vts.scanner.camera_image", &ScannerDesc::camera_image}}) {
    if (!has(attribute)) continue;
    const std::string& v = text(attribute);
    if (v != "true" && v != "false")
      throw fail(std::string("attribute ") + attribute + " = '" + v + "', expected 'true' or 'false'");
    s.*member = v == "true";
  }
  if (has("vts.error_model")) {
    const std::string& model = text("vts.error_model");
    if (model == kModelOn)
      info.error_model = true;
    else if (model != kModelOff)
      throw fail("attribute vts.error_model = '" + model + "', expected '" + kModelOn + "' or '" +
                 kModelOff + "'");
  }
  s.ideal = !info.error_model;
  if (const std::string why = validate(s); !why.empty())
    throw fail("attribute vts.scanner." + why);
  info.scene_name = text("vts.scene.name");
  info.scene_text = text("vts.scene.yaml");
  info.seed = integer<std::uint64_t>("vts.seed");
  const std::string& ref = text("vts.reference");
  if (ref == kReferenceKind)
    info.has_reference = true;
  else if (ref != kNoReference)
    throw fail("attribute vts.reference = '" + ref + "', expected '" + kReferenceKind +
               "' or '" + kNoReference + "'");

  const Imath::Box2i dw = header->dataWindow();
  width = dw.max.x - dw.min.x + 1;
  height = dw.max.y - dw.min.y + 1;
  if (dw.min.x != 0 || dw.min.y != 0)
    throw fail("dataWindow starts at (" + std::to_string(dw.min.x) + " " +
               std::to_string(dw.min.y) + "), expected (0 0)");
  if (width != s.points)
    throw fail("image width " + std::to_string(width) + " does not match vts.scanner.points = " +
               std::to_string(s.points));
  info.profiles = height;

  // The per-row channels: in part "rows", one column (version 2), or in the
  // one part, x-subsampled (version 1).
  auto part_name = [&](int part) { return in.header(part).hasName() ? in.header(part).name() : std::string(); };
  if (v1 && in.parts() != 1)
    throw fail("a " + std::string(kFormatV1) + " file has one part, this one " + std::to_string(in.parts()));
  if (!v1 && (in.parts() != 2 || part_name(0) != kProfilesPart || part_name(1) != kRowsPart)) {
    std::string parts;
    for (int i = 0; i < in.parts(); ++i) parts += (i ? ", '" : "'") + part_name(i) + "'";
    throw fail(std::string("a ") + kFormat + " file has two parts, '" + kProfilesPart + "' and '" + kRowsPart +
               "'; this one has " + std::to_string(in.parts()) + ": " + parts);
  }
  const Imf::Header& rows_header = in.header(v1 ? 0 : 1);
  row_xs = v1 ? width : 1;
  if (!v1) {
    const Imath::Box2i rdw = rows_header.dataWindow();
    if (rdw.min != Imath::V2i(0, 0) || rdw.max != Imath::V2i(0, height - 1))
      throw fail("part '" + std::string(kRowsPart) + "' has dataWindow (" + std::to_string(rdw.min.x) + " " +
                 std::to_string(rdw.min.y) + ") - (" + std::to_string(rdw.max.x) + " " +
                 std::to_string(rdw.max.y) + "), expected (0 0) - (0 " + std::to_string(height - 1) + ")");
  }

  slots = point_slots(info);
  for (int c : slots) require_channel(*header, kPointNames[c], Imf::FLOAT, 1);
  // Exact doubles when both bit channels are there, else the FLOAT rounding.
  for (int c = 0; c < 8; ++c) {
    const std::string name = kRowNames[c];
    require_channel(rows_header, name, Imf::FLOAT, row_xs);
    const bool hi = rows_header.channels().findChannel(kHiPrefix + name) != nullptr;
    const bool lo = rows_header.channels().findChannel(kLoPrefix + name) != nullptr;
    if (hi != lo)
      throw fail("channel '" + (hi ? kHiPrefix + name : kLoPrefix + name) + "' is there but '" +
                 (hi ? kLoPrefix + name : kHiPrefix + name) + "' is missing");
    if (hi) {
      require_channel(rows_header, kHiPrefix + name, Imf::UINT, row_xs);
      require_channel(rows_header, kLoPrefix + name, Imf::UINT, row_xs);
    }
    exact[c] = hi;
  }

  for (int c : slots) points[c].resize(std::size_t(kChunkRows) * width);
  for (int c = 0; c < 8; ++c) {
    row_f[c].resize(kChunkRows);
    row_hi[c].resize(kChunkRows);
    row_lo[c].resize(kChunkRows);
  }
  profiles_part.emplace(in, 0);
  if (!v1) rows_part.emplace(in, 1);
  open_direct();
}

void Reader::open_direct() {
  Direct& d = direct;
  if (v1 || std::endian::native != std::endian::little) return;
  switch (header->compression()) {
    case Imf::ZIP_COMPRESSION: d.zip = true, d.lines = 16; break;
    case Imf::ZIPS_COMPRESSION: d.zip = true, d.lines = 1; break;
    case Imf::NO_COMPRESSION: d.zip = false, d.lines = 1; break;
    default: return;
  }
  // A block is its rows one after the other, each row every channel in the
  // channel list's (alphabetical) order, little-endian.
  std::size_t at = 0;
  for (auto it = header->channels().begin(); it != header->channels().end(); ++it) {
    const Imf::Channel& ch = it.channel();
    if (ch.xSampling != 1 || ch.ySampling != 1) return;
    for (int c : slots)
      if (std::string_view(it.name()) == kPointNames[c]) d.offset[c] = at;
    at += std::size_t(width) * (ch.type == Imf::HALF ? 2 : 4);
  }
  d.row_bytes = at;
  d.usable = true;
}

// `raw`, block of `bytes` decoded bytes as stored, into `out`; false if it
// does not decode to exactly that many.
bool decode_block(bool zip, const std::vector<unsigned char>& raw, std::size_t bytes,
                  std::vector<unsigned char>& packed, std::vector<unsigned char>& out) {
  out.resize(bytes);
  if (!zip || raw.size() >= bytes) {
    // Stored as is (a compressor keeps a block it cannot shrink).
    if (raw.size() != bytes) return false;
    std::memcpy(out.data(), raw.data(), bytes);
    return true;
  }
  // OpenEXR's ZIP: zlib, then a byte-wise delta, then the two halves
  // interleaved (ImfZip.cpp).
  packed.resize(bytes);
  uLongf got = bytes;
  if (uncompress(packed.data(), &got, raw.data(), uLong(raw.size())) != Z_OK || got != bytes) return false;
  undo_zip_predictor(packed.data(), bytes);
  deinterleave(packed.data(), bytes, out.data());
  return true;
}

bool Reader::read_direct(int first, int rows) {
  Direct& d = direct;
  if (!d.usable) return false;
  const int b0 = first / d.lines, b1 = (first + rows - 1) / d.lines;
  const std::size_t count = std::size_t(b1 - b0 + 1);
  if (d.blocks.size() < count) d.blocks.resize(count);
  const bool have_first = d.cached == b0;
  d.cached = -1;
  auto block_bytes = [&](int b) { return std::size_t(std::min(d.lines, height - b * d.lines)) * d.row_bytes; };
  try {
    for (std::size_t k = have_first ? 1 : 0; k < count; ++k) {
      const char* data = nullptr;
      int size = 0;
      profiles_part->rawPixelData((b0 + int(k)) * d.lines, data, size);
      if (size < 0) return false;
      d.blocks[k].raw.assign(data, data + size);
    }
  } catch (const std::exception&) {
    return false;
  }
  // The blocks decoded on the vts threads (zlib is most of a read).
  std::atomic<bool> ok{true};
  parallel_for(count - (have_first ? 1 : 0), [&](std::size_t i) {
    const std::size_t k = i + (have_first ? 1 : 0);
    Direct::Block& b = d.blocks[k];
    if (!decode_block(d.zip, b.raw, block_bytes(b0 + int(k)), b.packed, b.data)) ok = false;
  });
  if (!ok) return false;
  for (int y = first; y < first + rows; ++y) {
    const int b = y / d.lines;
    const unsigned char* row = d.blocks[std::size_t(b - b0)].data.data() + std::size_t(y - b * d.lines) * d.row_bytes;
    for (int c : slots)
      std::memcpy(points[c].data() + std::size_t(y - first) * width, row + d.offset[c],
                  std::size_t(width) * sizeof(float));
  }
  // The last block, if the next read may start in it.
  if (count > 1) std::swap(d.blocks[0], d.blocks[count - 1]);
  d.cached = b1;
  return true;
}

void Reader::read_block(int first, int rows, Profile* profiles, Profile* reference,
                        std::array<double, 8>* row_values) {
  const std::size_t fstride = sizeof(float), ustride = sizeof(std::uint32_t);
  const int row_w = v1 ? width : 1;
  {
    const Imath::V2i origin(0, first);
    Imf::FrameBuffer fb, rows_fb;
    for (int c : slots)
      fb.insert(kPointNames[c],
                Imf::Slice::Make(Imf::FLOAT, points[c].data(), origin, width, kChunkRows,
                                 fstride, fstride * width));
    Imf::FrameBuffer& rfb = v1 ? fb : rows_fb;
    for (int c = 0; c < 8; ++c) {
      const std::string name = kRowNames[c];
      rfb.insert(name, Imf::Slice::Make(Imf::FLOAT, row_f[c].data(), origin, row_w, kChunkRows,
                                        fstride, fstride, row_xs, 1));
      if (!exact[c]) continue;
      rfb.insert(kHiPrefix + name, Imf::Slice::Make(Imf::UINT, row_hi[c].data(), origin, row_w,
                                                    kChunkRows, ustride, ustride, row_xs, 1));
      rfb.insert(kLoPrefix + name, Imf::Slice::Make(Imf::UINT, row_lo[c].data(), origin, row_w,
                                                    kChunkRows, ustride, ustride, row_xs, 1));
    }
    if (!read_direct(first, rows)) {
      profiles_part->setFrameBuffer(fb);
      profiles_part->readPixels(first, first + rows - 1);
    }
    if (rows_part) {
      rows_part->setFrameBuffer(rows_fb);
      rows_part->readPixels(first, first + rows - 1);
    }

    for (int r = 0; r < rows; ++r) {
      const int y = first + r;
      std::array<double, 8> v{};
      for (int c = 0; c < 8; ++c)
        v[c] = exact[c] ? std::bit_cast<double>((std::uint64_t(row_hi[c][r]) << 32) | row_lo[c][r])
                        : double(row_f[c][r]);
      if (row_values) row_values[r] = v;
      const Pose pose = pose_from_quat(Vec3(v[0], v[1], v[2]),
                                       Eigen::Quaterniond(v[3], v[4], v[5], v[6]));
      const std::size_t off = std::size_t(r) * width;
      auto take_valid = [&](std::vector<std::uint8_t>& out, int slot) {
        const float* valid = points[slot].data() + off;
        for (int i = 0; i < width; ++i) {
          if (valid[i] != 0.0f && valid[i] != 1.0f) {
            std::ostringstream s;
            s << "channel '" << kPointNames[slot] << "' row " << y << " column " << i << " = "
              << valid[i] << ", expected 0 or 1";
            throw fail(s.str());
          }
          out[i] = valid[i] == 1.0f ? 1 : 0;
        }
      };
      auto take = [&](Profile& p, int base) {
        p.resize(width);
        std::copy_n(points[base + 0].begin() + off, width, p.range_mm.begin());
        std::copy_n(points[base + 1].begin() + off, width, p.y_mm.begin());
        std::copy_n(points[base + 2].begin() + off, width, p.z_mm.begin());
        take_valid(p.valid, base + 3);
        p.world_from_sensor = pose;
        p.time_s = v[7];
        p.index = y;
      };
      take(profiles[r], 0);
      if (info.has_reference && reference) take(reference[r], 4);
      if (info.error_model) {
        Profile& p = profiles[r];
        std::copy_n(points[8].begin() + off, width, p.intensity.begin());
        std::copy_n(points[9].begin() + off, width, p.true_y_mm.begin());
        std::copy_n(points[10].begin() + off, width, p.true_z_mm.begin());
        take_valid(p.true_valid, 11);
      }
    }
  }
}

}  // namespace

// The C++ header reader trusts sizes the core does not see the same way: it
// reads a channel list up to its terminating empty name whatever the declared
// size, and allocates what variable-size attributes (string vectors,
// previews, opaque types) claim. So before it runs, walk the header as it
// will: every attribute within the file, the channel list ending exactly at its
// declared size, and besides strings only attribute types of a fixed size.
int fixed_attribute_size(const std::string& type) {
  static const std::pair<const char*, int> kSizes[] = {
      {"box2i", 16}, {"box2f", 16}, {"compression", 1}, {"lineOrder", 1}, {"float", 4},
      {"double", 8}, {"int", 4},    {"v2i", 8},         {"v2f", 8},       {"v2d", 16},
      {"v3i", 12},   {"v3f", 12},   {"v3d", 24},        {"m33f", 36},     {"m33d", 72},
      {"m44f", 64},  {"m44d", 128}, {"chromaticities", 32}, {"rational", 8}, {"timecode", 8},
      {"keycode", 28}, {"envmap", 1}, {"tiledesc", 9}, {"deepImageState", 1}};
  for (const auto& [name, size] : kSizes)
    if (type == name) return size;
  return -1;
}

// The first bytes of a file, read as far as they are asked for: a header
// walk reads the header, not the pixels after it.
class FilePrefix {
 public:
  explicit FilePrefix(const fs::path& path) : in_(path, std::ios::binary) {
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    size_ = ec ? 0 : static_cast<std::size_t>(size);
  }
  std::size_t size() const { return size_; }
  // Byte i (< size()).
  char operator[](std::size_t i) {
    while (i >= bytes_.size()) {
      const std::size_t old = bytes_.size();
      bytes_.resize(std::min(size_, std::max<std::size_t>(2 * old, 1 << 16)));
      in_.read(bytes_.data() + old, static_cast<std::streamsize>(bytes_.size() - old));
      if (bytes_.size() == old) return '\0';
    }
    return bytes_[i];
  }

 private:
  std::ifstream in_;
  std::size_t size_ = 0;
  std::vector<char> bytes_;
};

void check_header_layout(const fs::path& path) {
  FilePrefix bytes(path);
  const std::size_t n = bytes.size();
  const std::size_t max_name = (n > 5 && (bytes[5] & 0x04)) ? 255 : 31;  // long-names flag
  const bool multipart = n > 5 && (bytes[5] & 0x10);                      // multi-part flag
  std::size_t pos = 8;
  auto fail = [&](const std::string& why) { return ExrError(where(path) + ": header " + why); };
  auto read_cstr = [&](std::string& out) {
    out.clear();
    while (pos < n && bytes[pos] != '\0') {
      if (out.size() >= max_name) throw fail("has a name longer than " + std::to_string(max_name) + " bytes");
      out.push_back(bytes[pos++]);
    }
    if (pos >= n) throw fail("ends early (truncated file)");
    ++pos;
  };
  // One header, or (multi-part) headers until an empty one.
  for (int header = 0;; ++header) {
    for (int attribute = 0;; ++attribute) {
      std::string name, type;
      read_cstr(name);
      if (name.empty()) {
        if (!multipart) return;
        if (attribute == 0) return;  // the empty header after the last part's
        break;
      }
      read_cstr(type);
      if (pos + 4 > n) throw fail("ends early (truncated file)");
      std::uint32_t usize = 0;  // little-endian
      for (int b = 3; b >= 0; --b) usize = (usize << 8) | static_cast<unsigned char>(bytes[pos + b]);
      const auto size = static_cast<std::int32_t>(usize);
      pos += 4;
      if (size < 0 || pos + static_cast<std::size_t>(size) > n)
        throw fail("attribute '" + name + "' claims " + std::to_string(size) + " bytes, more than the file holds");
      const std::size_t end = pos + static_cast<std::size_t>(size);
      if (type == "chlist") {
        std::string channel;
        for (;;) {
          read_cstr(channel);
          if (channel.empty()) break;
          pos += 16;  // pixel type, pLinear, reserved, x and y sampling
          if (pos > end) throw fail("channel list overruns its declared size");
        }
        if (pos != end) throw fail("channel list does not end at its declared size");
      } else if (type != "string" && fixed_attribute_size(type) != size) {
        throw fail("attribute '" + name + "' of type '" + type + "' and size " + std::to_string(size) +
                   " is not one a vts profile file has");
      }
      pos = end;
    }
    if (header >= 2) throw fail("has more than the two parts a vts profile file has");
  }
}

// A vts file's pixels are at least four FLOAT channels of width x rows, and
// no codec shrinks such data more than deflate's ~1032:1.
constexpr double kMaxCompressionRatio = 1100.0;

// Checks the header with OpenEXR's bounds-checked C core before the C++
// library reads it: OpenEXR 3.1's C++ header reader allocates whatever size a
// (forged) attribute claims, and sizes the line-offset table from the data
// window. The core rejects inconsistent attribute sizes; we then refuse a data
// window wider than kMaxPoints or larger than the file can hold.
void check_header_sane(const fs::path& path) {
  std::string message;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.user_data = &message;
  init.error_handler_fn = [](exr_const_context_t ctxt, exr_result_t code, const char* msg) {
    std::string* out = nullptr;
    exr_get_user_data(ctxt, reinterpret_cast<void**>(&out));
    if (out && out->empty()) *out = msg ? msg : exr_get_default_error_message(code);
  };
  init.max_image_width = kMaxPoints;
  exr_context_t ctxt = nullptr;
  const exr_result_t rv = exr_start_read(&ctxt, path.c_str(), &init);
  struct Finish {
    exr_context_t* c;
    ~Finish() { exr_finish(c); }
  } finish{&ctxt};
  if (rv != EXR_ERR_SUCCESS)
    throw ExrError(where(path) + ": not a readable EXR: " +
                   (message.empty() ? exr_get_default_error_message(rv) : message));
  int parts = 0;
  exr_get_count(ctxt, &parts);
  if (parts < 1 || parts > 2)
    throw ExrError(where(path) + ": an EXR of " + std::to_string(parts) +
                   " parts, not a vts profile file (one or two parts)");
  const std::uintmax_t file_bytes = fs::file_size(path);
  for (int part = 0; part < parts; ++part) {
    exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
    exr_get_storage(ctxt, part, &storage);
    if (storage != EXR_STORAGE_SCANLINE)
      throw ExrError(where(path) + ": a tiled or deep EXR, not a vts profile file");
    exr_attr_box2i_t dw{};
    exr_get_data_window(ctxt, part, &dw);
    const double width = double(dw.max.x) - dw.min.x + 1.0;
    const double rows = double(dw.max.y) - dw.min.y + 1.0;
    // Part 0 holds at least four FLOAT channels, part 1 (the rows) at least eight.
    const double min_bytes_per_pixel = part == 0 ? 4.0 * 4.0 : 8.0 * 4.0;
    if (width < 1.0 || rows < 1.0 || width > kMaxPoints ||
        width * rows * min_bytes_per_pixel > kMaxCompressionRatio * static_cast<double>(file_bytes))
      throw ExrError(where(path) + ": dataWindow of " + std::to_string(static_cast<long long>(width)) +
                     " x " + std::to_string(static_cast<long long>(rows)) +
                     (part == 0 ? std::string() : " in part " + std::to_string(part)) +
                     " cannot be a vts profile file of " + std::to_string(file_bytes) +
                     " bytes (at most 4096 columns; truncated or corrupt)");
  }
}

namespace {

// Runs f, turning every exception but ExrError into one naming the file.
template <class F>
auto guarded(const fs::path& path, F&& f) {
  try {
    return f();
  } catch (const ExrError&) {
    throw;
  } catch (const std::exception& e) {
    throw ExrError(where(path) + ": " + e.what());
  } catch (...) {
    throw ExrError(where(path) + ": unknown error while reading");
  }
}

}  // namespace

struct ProfileExrReader::Impl {
  Reader reader;
  int next = 0;  // the next row to read
};

ProfileExrReader::ProfileExrReader(const fs::path& path) : impl_(std::make_unique<Impl>()) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw ExrError(where(path) + ": no such file");
  if (fs::is_directory(path, ec)) throw ExrError(where(path) + ": is a directory");
  {
    // OpenEXR's own message for a short non-EXR file is "Early end of file".
    std::ifstream probe(path, std::ios::binary);
    unsigned char magic[4] = {};
    if (!probe) throw ExrError(where(path) + ": cannot open: " + std::strerror(errno));
    probe.read(reinterpret_cast<char*>(magic), 4);
    if (probe.gcount() != 4 || magic[0] != 0x76 || magic[1] != 0x2f || magic[2] != 0x31 ||
        magic[3] != 0x01)
      throw ExrError(where(path) + ": not an OpenEXR file (no EXR magic number)");
  }
  impl_->reader.path = path;
  guarded(path, [&] {
    check_header_layout(path);
    check_header_sane(path);
    impl_->reader.open();
  });
}

ProfileExrReader::~ProfileExrReader() = default;

const ProfileFileInfo& ProfileExrReader::info() const { return impl_->reader.info; }

int ProfileExrReader::rows_read() const { return impl_->next; }

int ProfileExrReader::read(int max_rows, std::vector<Profile>& profiles, std::vector<Profile>* reference,
                           std::vector<std::array<double, 8>>* row_values) {
  Reader& r = impl_->reader;
  const int n = std::clamp(r.height - impl_->next, 0, std::max(max_rows, 1));
  profiles.resize(n);
  if (reference) reference->resize(r.info.has_reference ? n : 0);
  if (row_values) row_values->resize(n);
  guarded(r.path, [&] {
    for (int done = 0; done < n; done += kChunkRows)
      r.read_block(impl_->next + done, std::min(kChunkRows, n - done), profiles.data() + done,
                   reference && r.info.has_reference ? reference->data() + done : nullptr,
                   row_values ? row_values->data() + done : nullptr);
  });
  impl_->next += n;
  return n;
}

ProfileRecording read_profile_exr(const fs::path& path) {
  ProfileExrReader reader(path);
  ProfileRecording rec;
  rec.info = reader.info();
  reader.read(rec.info.profiles, rec.profiles, &rec.reference, &rec.row_values);
  return rec;
}

}  // namespace vts
