// seed 004 as a transition method: fit_biclothoid_corner (corner.hpp) sizes a biclothoid fillet by
// a tolerance or a start distance in the corner's plane, with the closed-form pair between two
// lines and the Bezier method as the fallback for a non-planar corner.

#include "blendbench/corner/biclothoid.hpp"

#include <string>
#include <utility>

#include "biclothoid_internal.hpp"
#include "blendbench/core/note.hpp"
#include "blendbench/corner/clothoid_blend.hpp"
#include "blendbench/corner/corner.hpp"

namespace blendbench {
using namespace biclothoid_detail;  // the helpers private to the biclothoid sources
namespace {

// Makes a fillet fitted in the corner's plane the corner's transition (false, with the fit's
// outcome and the corner's name in front of its message, when the fit failed).
bool use_fillet(const Outcome& outcome, const BiclothoidSolution& fillet, const CornerInput& corner,
                const CornerPlane& plane, CornerFit& fit) {
  if (!outcome.ok()) {
    fit.outcome = outcome;
    fit.outcome.message = corner.name + ": " + outcome.message;
    return false;
  }
  fit.transition = to_segments(fillet.curve, plane);
  fit.trim_in = fillet.a;
  fit.trim_out = fillet.b;
  return true;
}

// Two lines: the symmetric fillet in closed form (seed 004 section 7.1, seed 002 (Makino) eq. 9),
// sized as the clothoid method sizes it (line_pair). One named result, so it is built in place (the
// line-line fit is the fast path: a move of the fit on return was a few per cent of it).
CornerFit line_pair_fit(const CornerInput& corner, const PlanarCorner& geometry) {
  const double start_distance = corner.spec.start_distance;  // > 0: sized by it, not by tolerance
  CornerFit fit;
  fit.corner_case = geometry.angle <= kTangentAngle ? CornerCase::kTangent : CornerCase::kRegular;
  LinePair line = line_pair(corner, geometry, start_distance);
  use_line_pair(line, geometry.plane, start_distance > 0 ? line.pair.tangent_length : line.pair.deviation, fit);
  fit.note = std::move(line.shrink_note);
  return fit;
}

}  // namespace

CornerFit fit_biclothoid_corner(const CornerInput& corner) {
  const PlanarCorner geometry = planar_corner(corner.in, corner.out);
  if (auto special = clothoid_special_case(corner, geometry)) return *special;
  return fit_biclothoid_in_plane(corner, geometry);
}

CornerFit fit_biclothoid_in_plane(const CornerInput& corner, const PlanarCorner& geometry) {
  if (geometry.lines) return line_pair_fit(corner, geometry);
  const double tolerance = corner.spec.parameter;
  const double start_distance = corner.spec.start_distance;  // > 0: sized by it, not by tolerance
  CornerFit fit;
  fit.corner_case = geometry.angle <= kTangentAngle ? CornerCase::kTangent : CornerCase::kRegular;

  // seed 004 has no 3D form: a non-planar corner goes to the Bezier method (seed 000, quartic in 3D),
  // with its transition parameter set to the tolerance (a fillet that starts and ends within
  // that distance of the corner deviates less than it)
  if (!geometry.planar) {
    CornerFit bezier = fit_bezier_corner(corner);
    bezier.corner_case = CornerCase::kNonPlanar;
    bezier.fallback = Fallback::kBezier;
    if (!bezier.outcome.ok()) {
      bezier.outcome.message = "non-planar corner, Bezier fallback failed: " + bezier.outcome.message;
    }
    return bezier;
  }

  // seed 004 (Shahzadeh et al.) Algorithm 1 at the given start distance
  if (start_distance > 0) {
    const BiclothoidStartFit start_fit =
        fit_biclothoid_from_start(geometry.shapes, start_distance, corner.in_available, corner.out_available);
    if (!use_fillet(start_fit.outcome, start_fit.fillet, corner, geometry.plane, fit)) return fit;
    fit.parameter_used = start_fit.fillet.a;
    fit.exact_deviation = start_fit.deviation.max();
    using Limit = BiclothoidStartFit::Limit;
    fit.limited = start_fit.limit != Limit::kNone;
    if (start_fit.limit != Limit::kNone) {
      const Note::Literal why =
          start_fit.limit == Limit::kIncoming
              ? Note::Literal("limited by the incoming move (or an eighth of a turn of its arc)")
          : start_fit.limit == Limit::kOutgoing
              ? Note::Literal("the fillet must end within the outgoing move (or an eighth of a turn of its arc)")
              : Note::Literal("004 Algorithm 1 found no fillet starting further out");
      fit.note = Note::lengths("start distance shrunk from ", start_distance, " to ", start_fit.fillet.a, why);
    }
    return fit;
  }

  // seed 004 Algorithms 1 and 2 in the corner plane
  const BiclothoidToleranceFit tol_fit =
      fit_biclothoid_with_tolerance(geometry.shapes, tolerance, corner.in_available, corner.out_available);
  if (!use_fillet(tol_fit.outcome, tol_fit.fillet, corner, geometry.plane, fit)) return fit;
  fit.parameter_used = tol_fit.deviation.max();
  fit.exact_deviation = fit.parameter_used;
  fit.limited = tol_fit.limited;
  if (tol_fit.limited) {
    fit.note = Note::lengths("deviation ", fit.parameter_used, " below the tolerance ", tolerance,
                           "the fillet is limited by the move lengths (or an eighth of a turn of an arc)");
  } else if (!tol_fit.converged) {
    fit.note = Note::lengths("deviation ", fit.parameter_used, " below the tolerance ", tolerance,
                           "the tolerance loop (004 Algorithm 2) stopped before reaching it");
  }
  return fit;
}

}  // namespace blendbench
