#include "tracker/score.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

namespace vts::tracker {
namespace {

// "ambiguous: confidence 0.4, ..." -> "ambiguous"; "gap 6.1 mm outside [0, 5]" -> "gap mm outside".
std::string reason_kind(const std::string& reason) {
  // The words before a colon (the kind), or the whole reason, without its
  // numbers: "inside a wider groove (walls 45.2 and 45 deg, ...): ..." and
  // "gap 3.1 mm outside [0, 3]" are one kind whatever the values.
  const std::string head = reason.substr(0, reason.find(':'));
  std::string out;
  bool space = false;
  for (char ch : head) {
    if (std::isdigit(static_cast<unsigned char>(ch)) || ch == '.' || ch == '[' || ch == ']' || ch == ',' || ch == '-')
      continue;
    if (ch == ' ') {
      space = !out.empty();
      continue;
    }
    if (space) out += ' ';
    space = false;
    out += ch;
  }
  return out;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return kNotMeasured;
  const auto k = static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * (v.size() - 1) + 0.5);
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

}  // namespace

std::string_view to_string(Outcome o) {
  switch (o) {
    case Outcome::Right: return "right";
    case Outcome::Imprecise: return "imprecise";
    case Outcome::Rejected: return "rejected";
    case Outcome::False: return "false";
  }
  return "?";
}

Scored score(const TrackResult& r, const Truth& t, const ScoreParams& p) {
  Scored s;
  if (r.track_point) s.track_error_mm = (*r.track_point - t.track_point).norm();
  if (r.status != TrackStatus::Ok || !r.track_point) {
    s.outcome = Outcome::Rejected;
    return s;
  }
  if (std::isfinite(r.gap_mm) && std::isfinite(t.gap_mm)) s.gap_error_mm = std::abs(r.gap_mm - t.gap_mm);
  const double tol = t.noise_mm > 0.0 ? p.right_noisy_mm : p.right_ideal_mm;
  // NaN (a track point of NaN) is no right reading either.
  if (s.track_error_mm <= tol) s.outcome = Outcome::Right;
  else if (s.track_error_mm <= p.false_mm) s.outcome = Outcome::Imprecise;
  else s.outcome = Outcome::False;
  return s;
}

void Tally::add(const Scored& s, const TrackResult& r, const Truth& t) {
  ++profiles;
  if (s.outcome == Outcome::False) ++false_reads;
  if (t.hidden) {
    ++hidden;
    hidden_read += s.outcome != Outcome::Rejected;
  } else {
    switch (s.outcome) {
      case Outcome::Right: ++right; break;
      case Outcome::Imprecise: ++imprecise; break;
      case Outcome::False: break;
      case Outcome::Rejected: ++rejected; break;
    }
  }
  if (s.outcome == Outcome::Rejected) ++reject_reasons[reason_kind(r.reason)];
  if (s.outcome != Outcome::Rejected && !t.hidden && std::isfinite(r.track_sigma_mm) &&
      std::isfinite(s.track_error_mm)) {
    ++located;
    over_3_sigma += s.track_error_mm > 3.0 * r.track_sigma_mm;
  }
  if (s.outcome != Outcome::Rejected) {
    track_errors_mm.push_back(s.track_error_mm);
    if (std::isfinite(s.gap_error_mm)) gap_errors_mm.push_back(s.gap_error_mm);
  }
}

void ScoreTable::add(const TrackResult& r, const Truth& t, const ScoreParams& params) {
  rows[{t.joint, t.noise_mm}].add(score(r, t, params), r, t);
}

Tally ScoreTable::total(JointType joint) const {
  Tally all;
  for (const auto& [key, t] : rows) {
    if (key.first != joint) continue;
    all.profiles += t.profiles, all.right += t.right, all.imprecise += t.imprecise;
    all.rejected += t.rejected, all.false_reads += t.false_reads, all.hidden += t.hidden;
    all.hidden_read += t.hidden_read;
    all.located += t.located, all.over_3_sigma += t.over_3_sigma;
    all.track_errors_mm.insert(all.track_errors_mm.end(), t.track_errors_mm.begin(), t.track_errors_mm.end());
    all.gap_errors_mm.insert(all.gap_errors_mm.end(), t.gap_errors_mm.begin(), t.gap_errors_mm.end());
    for (const auto& [k, v] : t.reject_reasons) all.reject_reasons[k] += v;
  }
  return all;
}

std::string ScoreTable::markdown() const {
  std::string out =
      "| joint | noise (mm) | profiles (hidden) | right | imprecise | rejected | false reads | "
      "track error median / 95 % (mm) | gap error median / 95 % (mm) | over 3 stated rms |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n";
  char buf[320];
  auto pct = [](int k, int n) { return n > 0 ? 100.0 * k / n : 0.0; };
  auto row = [&](const char* joint, const char* noise, const Tally& t) {
    const int v = t.visible();
    char over[32] = "-";
    if (t.located > 0) std::snprintf(over, sizeof over, "%.1f %%", pct(t.over_3_sigma, t.located));
    std::snprintf(buf, sizeof buf,
                  "| %s | %s | %d (%d) | %.1f %% | %.1f %% | %.1f %% | %d | %.3f / %.3f | %.3f / %.3f | %s |\n", joint,
                  noise, t.profiles, t.hidden, pct(t.right, v), pct(t.imprecise, v), pct(t.rejected, v),
                  t.false_reads, quantile(t.track_errors_mm, 0.5), quantile(t.track_errors_mm, 0.95),
                  quantile(t.gap_errors_mm, 0.5), quantile(t.gap_errors_mm, 0.95), over);
    out += buf;
  };
  for (const JointType j : kAllJointTypes) {
    bool any = false;
    for (const auto& [key, t] : rows) {
      if (key.first != j) continue;
      any = true;
      char noise[32];
      if (key.second < 0.0) std::snprintf(noise, sizeof noise, "ideal");
      else std::snprintf(noise, sizeof noise, "%g", key.second);
      row(to_string(j).data(), noise, t);
    }
    if (any) row(to_string(j).data(), "all", total(j));
  }
  return out;
}

}  // namespace vts::tracker
