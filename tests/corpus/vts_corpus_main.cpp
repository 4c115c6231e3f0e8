// vts-corpus: writes corpus profiles as `vts track` CSV and their truth as JSON
// Lines (README.md).
#include "corpus.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace vc = vts_corpus;
namespace fs = std::filesystem;

namespace {

const char* const kUsage = R"(usage: vts-corpus --joint TYPE [options] --csv OUT.csv --truth OUT.jsonl

Writes profiles of the independent test corpus (tests/corpus/README.md):
the profiles as CSV in the format `vts track` reads (profile,y,z,valid) and
their ground truth as JSON Lines, one object per profile.

  --joint TYPE        fillet, corner, lap, butt, vgroove, or a groove of
                      docs/design/grooves.md: bevel, ugroove, jgroove,
                      vgroove-thick (required)
  --count N           number of profiles (default 1)
  --seed S            unsigned 64-bit seed (default 1); profile k of a set is
                      make_profile(joint, S + k); a recording uses S for all
  --noise SIGMA       range noise sigma in mm (default 0), or 'random' for one
                      of the corpus levels 0, 0.005, 0.02, 0.05, 0.1, 0.2 each
  --decoy             add a decoy feature 20-40 mm from the seam
  --recording         a sequence along the seam instead of independent profiles
  --decoy-every K     recording: a decoy on every K-th profile
  --ds MM             recording: travel per profile (default: drawn 0.1..1)
  --columns N         columns per profile, 16..4096 (default: drawn 256..2048)
  --standoff MM       root distance along the optical axis (default: drawn 50..250;
                      thick-plate grooves 100..400, raised to fit the groove)
  --ideal             no imperfections (noise still as --noise)
  --camera-out-of-plane  camera along the travel direction instead of in the laser plane
  --prob NAME=P       override a variant's probability (repeatable), e.g.
                      --prob backing_bar=1 --prob tack_weld=0
  --scene FILE        debug: each profile's cross-section in the sensor frame
                      (JSON Lines: edges [y0, z0, y1, z1, face], camera, range)
  --csv FILE          profiles out (written to FILE.tmp-PID, then renamed)
  --truth FILE        truth out (JSON Lines)
  --bench             generate the profiles, write nothing, print profiles/s
  --help              this text
)";

struct BadArgument : std::runtime_error {
  using std::runtime_error::runtime_error;
};

template <class T>
T parse_number(const std::string& option, const std::string& text) {
  T value{};
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || text.empty())
    throw BadArgument(option + ": '" + text + "' is not a valid number");
  return value;
}

nlohmann::ordered_json num(double v) {
  if (!std::isfinite(v)) return nullptr;
  return v;
}

nlohmann::ordered_json point(double y, double z) {
  if (!std::isfinite(y) || !std::isfinite(z)) return nullptr;
  return nlohmann::ordered_json{{"y", y}, {"z", z}};
}

nlohmann::ordered_json truth_json(int profile, const vc::Truth& t, bool ideal) {
  nlohmann::ordered_json j;
  j["profile"] = profile;
  j["joint"] = vc::joint_name(t.joint);
  j["track_point"] = point(t.track_y_mm, t.track_z_mm);
  j["gap_mm"] = num(t.gap_mm);
  j["mismatch_mm"] = num(t.mismatch_mm);
  j["angle_deg"] = num(t.angle_deg);
  j["step_mm"] = num(t.step_mm);
  j["depth_mm"] = num(t.depth_mm);
  j["area_mm2"] = num(t.area_mm2);
  // Grooves (docs/design/grooves.md); null for the other joints.
  j["wall_angle_a_deg"] = num(t.wall_angle_a_deg);
  j["wall_angle_b_deg"] = num(t.wall_angle_b_deg);
  j["top_width_mm"] = num(t.top_width_mm);
  j["fill_lowest"] = point(t.fill_lowest_y_mm, t.fill_lowest_z_mm);
  j["passes"] = t.passes >= 0 ? nlohmann::ordered_json(t.passes) : nlohmann::ordered_json(nullptr);
  nlohmann::ordered_json bps = nlohmann::ordered_json::object();
  for (const auto& [name, p] : t.break_points) bps[name] = point(p[0], p[1]);
  j["break_points"] = bps;
  j["decoy_point"] = point(t.decoy_y_mm, t.decoy_z_mm);
  j["tags"] = t.tags;
  j["noise_mm"] = t.noise_mm;
  // A profile without imperfections and noise: the "ideal" row of a score table.
  j["ideal"] = ideal && t.noise_mm == 0.0;
  j["columns"] = t.columns;
  j["standoff_mm"] = num(t.standoff_mm);
  j["seed"] = t.seed;
  j["index"] = t.index;
  j["s_mm"] = t.s_mm;
  nlohmann::ordered_json params = nlohmann::ordered_json::object();
  for (const auto& [name, v] : t.params) params[name] = num(v);
  j["params"] = params;
  return j;
}

nlohmann::json scene_json(int profile, const vc::Debug& d) {
  nlohmann::json edges = nlohmann::json::array();
  for (const auto& e : d.scene.edges) edges.push_back({e.a.x(), e.a.y(), e.b.x(), e.b.y(), e.face});
  return {{"profile", profile},
          {"edges", edges},
          {"camera", {d.sensor.camera_yz.x(), d.sensor.camera_yz.y()}},
          {"z_near_mm", d.sensor.z_near_mm},
          {"z_far_mm", d.sensor.z_far_mm},
          {"fan_deg", d.sensor.fan_deg}};
}

void append_csv(std::string& buf, int profile, const vc::Profile& p) {
  char tmp[64];
  const std::string k = std::to_string(profile);
  for (std::size_t i = 0; i < p.y.size(); ++i) {
    buf += k;
    if (!p.valid[i]) {
      buf += ",nan,nan,0\n";
      continue;
    }
    // Shortest round-trip float text: exact, locale-independent.
    buf += ',';
    buf.append(tmp, std::to_chars(tmp, tmp + sizeof tmp, p.y[i]).ptr);
    buf += ',';
    buf.append(tmp, std::to_chars(tmp, tmp + sizeof tmp, p.z[i]).ptr);
    buf += ",1\n";
  }
}

// A file written under a temporary name and renamed when complete. An
// existing target that is no regular file (/dev/null, a pipe) is written
// directly: renaming onto it would replace the device.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path) : path_(std::move(path)) {
    std::error_code ec;
    const bool special = fs::exists(path_, ec) && !fs::is_regular_file(path_, ec);
    tmp_ = special ? path_ : path_ + ".tmp-" + std::to_string(::getpid());
    committed_ = special;  // nothing to rename or remove
    f_ = std::fopen(tmp_.c_str(), "wb");
    if (!f_) throw std::runtime_error(path_ + ": cannot write " + tmp_);
  }
  ~AtomicFile() {
    if (f_) std::fclose(f_);
    if (!committed_) std::remove(tmp_.c_str());
  }
  void write(const std::string& s) {
    if (std::fwrite(s.data(), 1, s.size(), f_) != s.size()) throw std::runtime_error(path_ + ": write failed");
  }
  void commit() {
    const bool ok = std::fclose(f_) == 0;
    f_ = nullptr;
    if (!ok) throw std::runtime_error(path_ + ": write failed");
    if (tmp_ == path_) return;
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0) throw std::runtime_error(path_ + ": cannot rename " + tmp_);
    committed_ = true;
  }

 private:
  std::string path_, tmp_;
  std::FILE* f_ = nullptr;
  bool committed_ = false;
};

void check_output(const std::string& option, const std::string& path) {
  if (path.empty()) throw BadArgument(option + ": empty path");
  const fs::path dir = fs::path(path).parent_path();
  std::error_code ec;
  if (!dir.empty() && !fs::is_directory(dir, ec)) throw BadArgument(option + ": directory '" + dir.string() + "' does not exist");
  if (fs::is_directory(path, ec)) throw BadArgument(option + ": '" + path + "' is a directory");
}

int run(int argc, char** argv) {
  std::optional<vc::Joint> joint;
  int count = 1;
  std::uint64_t seed = 1;
  bool recording = false, bench = false;
  int decoy_every = 0;
  double ds_mm = 0;
  std::string csv_path, truth_path, scene_path;
  vc::Options options;
  std::vector<std::string> args(argv + 1, argv + argc);
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw BadArgument(a + ": missing value");
      return args[++i];
    };
    if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      return 0;
    } else if (a == "--joint") {
      const std::string& v = value();
      joint = vc::joint_from_name(v);
      if (!joint)
        throw BadArgument("--joint: unknown joint '" + v +
                          "': expected fillet, corner, lap, butt, vgroove, bevel, ugroove, jgroove or vgroove-thick");
    } else if (a == "--count") {
      count = parse_number<int>(a, value());
      if (count < 1 || count > 10'000'000) throw BadArgument("--count: " + std::to_string(count) + " outside 1..10000000");
    } else if (a == "--seed") {
      seed = parse_number<std::uint64_t>(a, value());
    } else if (a == "--noise") {
      const std::string& v = value();
      if (v == "random") {
        options.noise_mm = -1;
      } else {
        options.noise_mm = parse_number<double>(a, v);
        if (!(options.noise_mm >= 0 && options.noise_mm <= 5)) throw BadArgument("--noise: " + v + " outside 0..5 mm");
      }
    } else if (a == "--bench") {
      bench = true;
    } else if (a == "--decoy") {
      options.decoy = true;
    } else if (a == "--recording") {
      recording = true;
    } else if (a == "--decoy-every") {
      decoy_every = parse_number<int>(a, value());
      if (decoy_every < 1) throw BadArgument("--decoy-every: must be >= 1");
    } else if (a == "--ds") {
      ds_mm = parse_number<double>(a, value());
      if (!(ds_mm > 0 && ds_mm <= 100)) throw BadArgument("--ds: must lie in (0, 100] mm");
    } else if (a == "--columns") {
      options.columns = parse_number<int>(a, value());
      if (options.columns < 16 || options.columns > 4096) throw BadArgument("--columns: must lie in 16..4096");
    } else if (a == "--standoff") {
      options.standoff_mm = parse_number<double>(a, value());
      if (!(options.standoff_mm >= 10 && options.standoff_mm <= 2000)) throw BadArgument("--standoff: must lie in 10..2000 mm");
    } else if (a == "--ideal") {
      options.imperfections = false;
    } else if (a == "--camera-out-of-plane") {
      options.camera_in_laser_plane = false;
    } else if (a == "--prob") {
      const std::string& v = value();
      const auto eq = v.find('=');
      if (eq == std::string::npos || eq == 0) throw BadArgument("--prob: expected NAME=P, got '" + v + "'");
      const double p = parse_number<double>(a, v.substr(eq + 1));
      if (!(p >= 0 && p <= 1)) throw BadArgument("--prob: " + v + ": probability outside [0, 1]");
      options.probability[v.substr(0, eq)] = p;
    } else if (a == "--csv") {
      csv_path = value();
    } else if (a == "--truth") {
      truth_path = value();
    } else if (a == "--scene") {
      scene_path = value();
    } else {
      throw BadArgument("unknown option '" + a + "' (see --help)");
    }
  }
  if (!joint) throw BadArgument("--joint is required (see --help)");
  if (csv_path.empty() && truth_path.empty() && !bench) throw BadArgument("nothing to write: give --csv and/or --truth");
  if (!recording && (decoy_every > 0 || ds_mm > 0)) throw BadArgument("--decoy-every and --ds need --recording");
  if (!csv_path.empty()) check_output("--csv", csv_path);
  if (!truth_path.empty()) check_output("--truth", truth_path);
  if (!scene_path.empty()) check_output("--scene", scene_path);
  options.keep_debug = !scene_path.empty();
  if (!csv_path.empty() && fs::path(csv_path) == fs::path(truth_path)) throw BadArgument("--csv and --truth name the same file");
  // Unknown --prob names are bad arguments too: find them before writing.
  try {
    for (const auto& [name, p] : options.probability) (void)vc::default_probability(*joint, name);
  } catch (const std::invalid_argument& e) {
    std::string known;
    for (const auto& n : vc::variant_names(*joint)) known += (known.empty() ? "" : ", ") + n;
    throw BadArgument(std::string("--prob: ") + e.what() + " (known: " + known + ")");
  }

  vc::RecordingOptions ro;
  ro.profile = options;
  ro.ds_mm = ds_mm;
  ro.decoy_every = decoy_every;
  auto make = [&](int k) {
    return recording ? vc::make_recording_profile(*joint, seed, count, k, ro)
                     : vc::make_profile(*joint, seed + static_cast<std::uint64_t>(k), options);
  };
  if (bench) {
    const auto start = std::chrono::steady_clock::now();
    long columns = 0;
    for (int k = 0; k < count; ++k) columns += static_cast<long>(make(k).y.size());
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << count << " " << vc::joint_name(*joint) << " profiles (" << columns << " columns) in " << s
              << " s: " << count / s << " profiles/s\n";
    return 0;
  }
  std::optional<AtomicFile> csv, truth;
  if (!csv_path.empty()) {
    csv.emplace(csv_path);
    csv->write("profile,y,z,valid\n");
  }
  if (!truth_path.empty()) truth.emplace(truth_path);
  std::optional<AtomicFile> scene;
  if (!scene_path.empty()) scene.emplace(scene_path);
  std::string buf;
  for (int k = 0; k < count; ++k) {
    const vc::Profile p = make(k);
    if (csv) {
      buf.clear();
      append_csv(buf, k, p);
      csv->write(buf);
    }
    if (truth) truth->write(truth_json(k, p.truth, !options.imperfections).dump() + "\n");
    if (scene) scene->write(scene_json(k, *p.debug).dump() + "\n");
  }
  if (scene) scene->commit();
  if (csv) csv->commit();
  if (truth) truth->commit();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const BadArgument& e) {
    std::cerr << "vts-corpus: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "vts-corpus: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "vts-corpus: " << e.what() << "\n";
    return 1;
  }
}
