#include "blendbench/app/sensitivity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "blendbench/core/units.hpp"

namespace blendbench {
namespace {

// A figure in the JSON's unit (s stay s, m become mm, divided as metrics_json divides them, so
// the two write the same numbers).
double in_json_unit(Headline metric, double si) { return metric == Headline::kCycleTime ? si : si / kMm; }

// What the better variant does, as the statement says it.
std::string_view verb(Headline metric) {
  switch (metric) {
    case Headline::kCycleTime:
      return "is faster (settled cycle time) than";
    case Headline::kContourProgrammed:
      return "has a smaller contour error against the program than";
    case Headline::kContourPlanned:
      return "has a smaller contour error against the plan than";
    case Headline::kVibrationCorner:
      return "vibrates less after the corners than";
    case Headline::kVibrationFinal:
      return "vibrates less after the stop than";
  }
  return "";
}

// What two equal figures are, as the statement says it.
std::string_view equal_text(Headline metric) {
  switch (metric) {
    case Headline::kCycleTime:
      return "settled cycle time";
    case Headline::kContourProgrammed:
      return "contour error against the program";
    case Headline::kContourPlanned:
      return "contour error against the plan";
    case Headline::kVibrationCorner:
      return "residual vibration after the corners";
    case Headline::kVibrationFinal:
      return "residual vibration after the stop";
  }
  return "";
}

// A percentage as the statements write it: one decimal, two below 1 % (the small differences of
// a cycle time are where the order is in question).
std::string percent_text(double p) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, std::abs(p) < 0.995 ? "%.2f" : "%.1f", p);
  return buffer;
}

// "3.1-3.4 %", "-0.5 to 3.4 %" (a range that crosses zero), "3.1 %" (one value).
std::string range_text(double lo, double hi) {
  const std::string a = percent_text(lo), b = percent_text(hi);
  if (a == b) return a + " %";
  return a + (lo < 0 ? " to " : "-") + b + " %";
}

int sign(double x) { return (x > 0) - (x < 0); }

// The figure of a run, none when it has none (not clean, or the metric missing).
std::optional<double> figure(const SensitivityRun& run, Headline metric) {
  if (!run.figures) return std::nullopt;
  return (*run.figures)[static_cast<std::size_t>(metric)];
}

// (worse - better) / worse in % (0 when both are 0).
double difference(double better, double worse) { return worse != 0 ? 100 * (worse - better) / worse : 0.0; }

nlohmann::json optional_json(const std::optional<double>& v, Headline metric) {
  return v ? nlohmann::json(in_json_unit(metric, *v)) : nlohmann::json();
}

}  // namespace

std::string_view headline_key(Headline metric) {
  switch (metric) {
    case Headline::kCycleTime:
      return "cycle_time_s";
    case Headline::kContourProgrammed:
      return "contour_error_programmed_max_mm";
    case Headline::kContourPlanned:
      return "contour_error_planned_max_mm";
    case Headline::kVibrationCorner:
      return "residual_vibration_corner_max_mm";
    case Headline::kVibrationFinal:
      return "residual_vibration_final_mm";
  }
  return "";
}

std::string_view to_string(OrderHolds holds) {
  switch (holds) {
    case OrderHolds::kAll:
      return "all";
    case OrderHolds::kSome:
      return "some";
    case OrderHolds::kNone:
      return "none";
  }
  return "";
}

HeadlineFigures headline_figures(const Metrics& m) {
  double corners = 0;
  for (const Vibration& v : m.vibration_corners) corners = std::max(corners, v.peak_to_peak);
  return {m.cycle_time, m.contour_error_programmed_max, m.contour_error_planned_max, corners,
          m.vibration_final.peak_to_peak};
}

FigureRange figure_range(const SensitivityVariant& variant, Headline metric) {
  FigureRange out;
  out.nominal = figure(variant.nominal, metric);
  const auto add = [&](const std::optional<double>& v) {
    if (!v) return;
    out.min = std::min(out.min.value_or(*v), *v);
    out.max = std::max(out.max.value_or(*v), *v);
    ++out.models;
  };
  add(out.nominal);
  for (const SensitivityRun& run : variant.perturbed) add(figure(run, metric));
  return out;
}

std::vector<Conclusion> conclude(const std::vector<Perturbation>& perturbations,
                                 const std::vector<SensitivityVariant>& variants) {
  std::vector<Conclusion> out;
  for (std::size_t i = 0; i < variants.size(); ++i) {
    for (std::size_t j = i + 1; j < variants.size(); ++j) {
      for (const Headline metric : kAllHeadlines) {
        const std::optional<double> a = figure(variants[i].nominal, metric), b = figure(variants[j].nominal, metric);
        if (!a || !b) continue;
        // the nominal order: the lower figure is the better one
        const bool swap = *b < *a;
        const SensitivityVariant& better = swap ? variants[j] : variants[i];
        const SensitivityVariant& worse = swap ? variants[i] : variants[j];
        Conclusion c;
        c.better = better.name;
        c.worse = worse.name;
        c.metric = metric;
        c.difference_nominal = difference(std::min(*a, *b), std::max(*a, *b));
        c.difference_min = c.difference_max = c.difference_nominal;
        const int nominal_sign = sign(std::max(*a, *b) - std::min(*a, *b));
        // each perturbed model: does the order hold there?
        for (std::size_t k = 0; k < perturbations.size(); ++k) {
          ++c.models;
          const std::string& name = perturbations[k].name;
          const std::optional<double> x = k < better.perturbed.size() ? figure(better.perturbed[k], metric) : std::nullopt;
          const std::optional<double> y = k < worse.perturbed.size() ? figure(worse.perturbed[k], metric) : std::nullopt;
          if (!x || !y) {
            c.unresolved.push_back(name);
            c.fails_in.push_back(name);
            continue;
          }
          const double d = difference(*x, *y);
          c.difference_min = std::min(c.difference_min, d);
          c.difference_max = std::max(c.difference_max, d);
          if (sign(*y - *x) == nominal_sign) {
            ++c.holds;
          } else {
            c.fails_in.push_back(name);
          }
        }
        c.holds_in = c.holds == c.models ? OrderHolds::kAll : c.holds == 0 ? OrderHolds::kNone : OrderHolds::kSome;
        c.statement = nominal_sign == 0
                          ? better.name + " and " + worse.name + " have the same " + std::string(equal_text(metric))
                          : better.name + " " + std::string(verb(metric)) + " " + worse.name + " by " +
                                range_text(c.difference_min, c.difference_max);
        out.push_back(std::move(c));
      }
    }
  }
  return out;
}

OrderSpread order_spread(const Sensitivity& study) {
  return [&study](const std::string& a, const std::string& b) -> std::optional<OrderHolds> {
    for (const Conclusion& c : study.conclusions) {
      if (c.metric != Headline::kCycleTime) continue;
      if ((c.better == a && c.worse == b) || (c.better == b && c.worse == a)) return c.holds_in;
    }
    return std::nullopt;
  };
}

nlohmann::json sensitivity_json(const Sensitivity& s) {
  nlohmann::json perturbations = nlohmann::json::array();
  for (const Perturbation& p : s.perturbations) {
    perturbations.push_back({{"name", p.name},
                             {"stiffness_scale", p.stiffness_scale},
                             {"inertia_scale", p.inertia_scale},
                             {"friction_scale", p.friction_scale},
                             {"extra_delay_ticks", p.extra_delay_ticks}});
  }
  const auto run_json = [](const std::string& model, const SensitivityRun& run) {
    nlohmann::json out = {{"model", model}, {"status", run.status}};
    if (!run.message.empty()) out["message"] = run.message;
    for (const Headline metric : kAllHeadlines) {
      out[std::string(headline_key(metric))] = optional_json(figure(run, metric), metric);
    }
    return out;
  };
  nlohmann::json variants = nlohmann::json::array();
  for (const SensitivityVariant& v : s.variants) {
    nlohmann::json runs = nlohmann::json::array();
    runs.push_back(run_json("nominal", v.nominal));
    for (std::size_t k = 0; k < v.perturbed.size() && k < s.perturbations.size(); ++k) {
      runs.push_back(run_json(s.perturbations[k].name, v.perturbed[k]));
    }
    nlohmann::json ranges = nlohmann::json::object();
    for (const Headline metric : kAllHeadlines) {
      const FigureRange r = figure_range(v, metric);
      ranges[std::string(headline_key(metric))] = {{"nominal", optional_json(r.nominal, metric)},
                                                  {"min", optional_json(r.min, metric)},
                                                  {"max", optional_json(r.max, metric)},
                                                  {"models", r.models}};
    }
    variants.push_back({{"variant", v.name}, {"ranges", ranges}, {"runs", runs}});
  }
  nlohmann::json conclusions = nlohmann::json::array();
  for (const Conclusion& c : s.conclusions) {
    conclusions.push_back({{"metric", std::string(headline_key(c.metric))},
                           {"better", c.better},
                           {"worse", c.worse},
                           {"statement", c.statement},
                           {"holds_in", std::string(to_string(c.holds_in))},
                           {"models", c.models},
                           {"holds", c.holds},
                           {"difference_percent", {{"nominal", c.difference_nominal}, {"min", c.difference_min}, {"max", c.difference_max}}},
                           {"fails_in", c.fails_in},
                           {"unresolved", c.unresolved}});
  }
  return {{"method",
           "one at a time: every variant that ran cleanly on the nominal model re-run on each perturbed model, which "
           "changes one parameter; the plan and the joint reference are the nominal run's (they do not depend on the "
           "dynamics), the drive is re-tuned on the perturbed arm (its measurement delay is not)"},
          {"models", s.perturbations.size()},
          {"perturbations", perturbations},
          {"jobs", s.jobs},
          {"wall_time_s", s.wall_time},
          {"skipped", s.skipped},
          {"notes", s.notes},
          {"variants", variants},
          {"conclusions", conclusions}};
}

}  // namespace blendbench
