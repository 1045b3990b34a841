#pragma once
// Internal to the app, built with rendering only: what a run records for its videos and how it
// renders them (render/film.hpp draws the frames), with a progress bar on stderr.

#include <filesystem>
#include <vector>

#include "blendbench/io/run_inputs.hpp"
#include "blendbench/program/path.hpp"
#include "blendbench/render/film.hpp"
#include "blendbench/sim/simulator.hpp"

namespace blendbench {

// The rate at which a run records the arm's pose (Hz): the video's frame rate, times the
// comparison's slow motion when a comparison is made.
double pose_rate(const RunInputs& scenario, bool compare);

// Makes `run` record the arm's pose (qpos) into `film` at `rate` Hz from t = 0, reserving room
// for `duration` s of a model with `nq` positions.
void record_poses(VariantFilm& film, RunOptions& run, double rate, double duration, int nq);

// A path sampled densely enough for a zoomed view (world frame, m).
std::vector<Vec3> film_polyline(const Path& path);

// The settings every video of the scenario shares: size, rate, camera, the programmed path of
// `program` (the variants differ in transitions only, not in the moves).
FilmSettings film_settings(const RunInputs& scenario, const Program& program);

// Render a video to `file` with a progress bar on stderr when it is a terminal, and one summary
// line there either way ("video NAME: N frames WxH in S s (F fps) -> FILE"). Return the wall
// time in s. Throw as write_variant_video / write_compare_video do.
double render_variant_video(const mjModel& m, const VariantFilm& film, const FilmSettings& settings,
                            const std::filesystem::path& file);
double render_compare_video(const mjModel& m, const std::vector<VariantFilm>& films, const FilmSettings& settings,
                            const std::filesystem::path& file);

}  // namespace blendbench
