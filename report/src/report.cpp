#include "blendbench/report/report.hpp"

#include <algorithm>
#include <cmath>

#include "blendbench/report/output.hpp"

namespace blendbench {
namespace {

// mm from m, for output
constexpr double kMm = 1e3;

// Appends "v0,v1,...\n".
void append_row(std::string& out, std::initializer_list<double> values) {
  bool first = true;
  for (const double v : values) {
    if (!first) out += ',';
    out += format_number(v, 12);
    first = false;
  }
  out += '\n';
}

int sample_count(double len, double ds) { return std::max(1, static_cast<int>(std::ceil(len / ds - 1e-9))); }

// A JSON number, or null when not finite (JSON has no infinity).
nlohmann::json finite_or_null(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

}  // namespace

std::string path_csv(const Path& path, double ds) {
  std::string out = "s,x,y,z,tx,ty,tz,kappa\n";
  if (path.pieces().empty()) return out;
  for (std::size_t k = 0; k < path.pieces().size(); ++k) {
    const Segment& seg = path.pieces()[k].segment;
    const double len = length(seg);
    const int n = sample_count(len, ds);
    // every piece contributes its start; the last piece also its end
    const int last = k + 1 == path.pieces().size() ? n : n - 1;
    for (int i = 0; i <= last; ++i) {
      const double s = len * i / n;
      const Vec3 p = point(seg, s);
      const Vec3 t = tangent(seg, s);
      const double kappa = curvature_vector(seg, s).norm();
      append_row(out, {(path.offset(k) + s) * kMm, p.x() * kMm, p.y() * kMm, p.z() * kMm, t.x(), t.y(), t.z(),
                       kappa / kMm});
    }
  }
  return out;
}

std::string program_csv(const Program& program, double ds) {
  std::string out = "s,x,y,z\n";
  double offset = 0;
  for (std::size_t k = 0; k < program.moves.size(); ++k) {
    const Primitive& g = program.moves[k].geometry;
    const double len = length(g);
    const int n = sample_count(len, ds);
    const int last = k + 1 == program.moves.size() ? n : n - 1;
    for (int i = 0; i <= last; ++i) {
      const double s = len * i / n;
      const Vec3 p = point(g, s);
      append_row(out, {(offset + s) * kMm, p.x() * kMm, p.y() * kMm, p.z() * kMm});
    }
    offset += len;
  }
  return out;
}

nlohmann::json corners_json(const Path& path) {
  nlohmann::json out = nlohmann::json::array();
  for (const CornerReport& c : path.corners) {
    out.push_back({
        {"index", c.index},
        {"method", std::string(to_string(c.method))},
        {"case", std::string(to_string(c.corner_case))},
        {"fallback", std::string(to_string(c.fallback))},
        {"note", c.note},
        {"parameter_mm", c.parameter * kMm},
        {"length_mm", c.length * kMm},
        {"deviation_mm", c.deviation * kMm},
        {"kappa_max_per_mm", c.kappa_max / kMm},
        {"sharpness_max_per_mm2", c.sharpness_max / (kMm * kMm)},
        {"feed_max_mm_per_min", finite_or_null(c.feed_max * kMm * 60.0)},
        {"trim_in_mm", c.trim_in * kMm},
        {"trim_out_mm", c.trim_out * kMm},
        {"stop", c.stop},
    });
  }
  return out;
}

std::string timed_csv(const Path& path, const Timing& timing) {
  std::string out = "t,s,x,y,z,v,a,j,kappa\n";
  out.reserve(timing.samples.size() * 96);
  for (const TimedSample& sample : timing.samples) {
    const Vec3 p = path.point(sample.s);
    const double kappa = path.curvature_vector(sample.s).norm();
    append_row(out, {sample.t, sample.s * kMm, p.x() * kMm, p.y() * kMm, p.z() * kMm, sample.v * kMm, sample.a * kMm,
                     sample.j * kMm, kappa / kMm});
  }
  return out;
}

nlohmann::json plan_summary_json(const Path& path, const Timing& timing) {
  nlohmann::json pieces = nlohmann::json::array();
  for (const PieceTiming& p : timing.pieces) {
    const PathPiece& piece = path.pieces()[p.piece];
    pieces.push_back({{"index", p.piece},
                      {"move", piece.move},
                      {"corner", piece.corner},
                      {"length_mm", length(piece.segment) * kMm},
                      {"v_peak_mm_s", p.v_peak * kMm},
                      {"binding", p.binding}});
  }
  return {{"cycle_time_s", timing.cycle_time},
          {"path_length_mm", path.length() * kMm},
          {"feed_share", timing.feed_share},
          {"servo_period_s", timing.dt},
          {"corners", corners_json(path)},
          {"pieces", pieces}};
}

}  // namespace blendbench
