#include "run_video.hpp"

#include <chrono>
#include <cmath>

#include "blendbench/report/output.hpp"
#include "progress_bar.hpp"

namespace blendbench {
namespace {

// Sampling of the paths a film draws (m): well below a pixel of a zoomed corner (~0.05 mm), so a
// transition's curve shows no facets; lines are simplified to the pixel before they are drawn.
constexpr double kFilmStep = 0.2e-3;

CameraSpec camera_spec(const VideoCamera& c) {
  CameraSpec spec;
  spec.mode = c.mode == CameraMode::kFixed ? CameraSpec::Mode::kFixed
              : c.mode == CameraMode::kTcp ? CameraSpec::Mode::kTcp
                                           : CameraSpec::Mode::kPart;
  spec.part.fill = c.fill;
  spec.part.azimuth_deg = c.azimuth_deg;
  spec.part.elevation_deg = c.elevation_deg;
  spec.position = c.position;
  spec.look_at = c.look_at;
  spec.distance = c.distance;
  spec.fovy_deg = c.fovy_deg;
  return spec;
}

// Renders `video` frame by frame with a progress bar, then prints the summary line.
template <class Render>
double render_with_progress(const std::string& what, int width, int height, const std::filesystem::path& file,
                            Render render) {
  const ProgressBar bar;
  const int frames = render([&](int done, int total) {
    bar.draw(static_cast<std::size_t>(done), static_cast<std::size_t>(total),
             what + ": frame " + std::to_string(done) + "/" + std::to_string(total));
  });
  const double seconds = bar.elapsed();
  bar.finish(what + ": " + std::to_string(frames) + " frames " + std::to_string(width) + "x" + std::to_string(height) +
             " in " + format_fixed(seconds, 1) + " s (" + format_fixed(frames / std::max(seconds, 1e-9), 1) + " fps) -> " +
             file.string());
  return seconds;
}

}  // namespace

double pose_rate(const RunInputs& scenario, bool compare) {
  return scenario.video.fps * (compare ? CompareVideo::kSlowMotion : 1);
}

void record_poses(VariantFilm& film, RunOptions& run, double rate, double duration, int nq) {
  film.pose_rate_hz = rate;
  film.qpos.clear();
  film.qpos.reserve(static_cast<std::size_t>(std::ceil(duration * rate) + 2) * static_cast<std::size_t>(nq));
  run.frame_rate = rate;
  run.on_frame = [&film](const mjModel& m, const mjData& d, double) { film.qpos.insert(film.qpos.end(), d.qpos, d.qpos + m.nq); };
}

std::vector<Vec3> film_polyline(const Path& path) {
  const int n = std::max(2, static_cast<int>(std::ceil(path.length() / kFilmStep)));
  std::vector<Vec3> points;
  points.reserve(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) points.push_back(path.point(path.length() * i / n));
  return points;
}

FilmSettings film_settings(const RunInputs& scenario, const Program& program) {
  FilmSettings s;
  s.width = scenario.video.width;
  s.height = scenario.video.height;
  s.fps = scenario.video.fps;
  s.camera = camera_spec(scenario.video.camera);
  s.scenario = scenario.name;
  s.program_frame = scenario.frame;
  // the tool on the flange, drawn when the scenario sets one
  if (scenario.robot.tool.matrix() != Eigen::Matrix4d::Identity()) s.tool = scenario.robot.tool;
  for (const Move& m : program.moves) {
    const double len = length(m.geometry);
    const int n = std::max(2, static_cast<int>(std::ceil(len / kFilmStep)));
    for (int i = 0; i <= n; ++i) s.programmed.push_back(point(m.geometry, len * i / n));
  }
  return s;
}

double render_variant_video(const mjModel& m, const VariantFilm& film, const FilmSettings& settings,
                            const std::filesystem::path& file) {
  return render_with_progress("video " + film.name, settings.width, settings.height, file, [&](const FilmProgress& progress) {
    return write_variant_video(m, film, settings, file.string(), progress);
  });
}

double render_compare_video(const mjModel& m, const std::vector<VariantFilm>& films, const FilmSettings& settings,
                            const std::filesystem::path& file) {
  const CompareLayout layout = compare_layout(static_cast<int>(films.size()), settings.width, settings.height);
  return render_with_progress("comparison", layout.width, layout.height, file, [&](const FilmProgress& progress) {
    return write_compare_video(m, films, settings, file.string(), progress);
  });
}

}  // namespace blendbench
