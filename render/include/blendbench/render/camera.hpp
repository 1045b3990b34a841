#pragma once
// Cameras of the videos: a pinhole pose in the world frame (the robot base frame, m), the
// projection it implies, and the rules that place it: on the part (the default), at a fixed pose,
// or following the TCP.
//
// Angles follow one convention everywhere: the camera stands at azimuth `azimuth_deg` (measured
// in the world x-y plane from +x towards +y) and elevation `elevation_deg` (above the horizontal,
// positive: looking down) as seen from the point it looks at.

#include <optional>
#include <vector>

#include "blendbench/core/geometry.hpp"

namespace blendbench {

// A pinhole camera: eye position, unit viewing direction, unit image-up direction perpendicular
// to it, and the vertical field of view of the whole image (symmetric frustum, square pixels).
struct CameraPose {
  Vec3 eye = Vec3(1, -1, 1);
  Vec3 forward = Vec3(-1, 1, -1).normalized();
  Vec3 up = Vec3(-1, 1, 2).normalized();
  double fovy_deg = 45;

  [[nodiscard]] Vec3 right() const { return forward.cross(up); }
};

// Where a world point lands in an image of width x height pixels: column u and row v measured
// from the top-left corner (pixels, continuous), and its depth along `forward` (m; <= 0 means
// behind the eye, where u and v are meaningless).
struct Projection {
  double u = 0, v = 0, depth = 0;
};
Projection project(const CameraPose& camera, const Vec3& p, int width, int height);

// World length of one pixel at `depth` (m) in front of the camera, for an image `height` pixels tall.
double pixel_size(const CameraPose& camera, double depth, int height);

// The camera `distance` (m, > 0) from `target`, standing at azimuth / elevation (degrees, as
// above; elevation clamped to +-89.9 so image-up stays defined) and looking at it.
CameraPose orbit_camera(const Vec3& target, double azimuth_deg, double elevation_deg, double distance, double fovy_deg);

// The camera at `eye` looking at `target` (distinct points), image-up as close to world +z as
// the direction allows (world +y when looking straight up or down).
CameraPose look_at(const Vec3& eye, const Vec3& target, double fovy_deg);

// A view direction as the azimuth and elevation of the camera seen from its target (degrees).
struct ViewAngles {
  double azimuth_deg = 0, elevation_deg = 0;
};

// The default view of a path (points in the world frame, m; `base` the robot base): from the
// points' best-fit plane (least-squares), the camera looks at the plane kViewFromNormalDeg away
// from its normal (the normal taken on the tool's side: up, or towards the base for a wall), from
// the side of the part away from the robot base, turned kViewTurnDeg about the normal so the
// path's lines are not seen edge-on. A straight path takes the vertical plane through it (or the
// plane facing the base when it is vertical); a single point (or none) is seen from above-front.
inline constexpr double kViewFromNormalDeg = 40;
inline constexpr double kViewTurnDeg = 30;
ViewAngles default_view(const std::vector<Vec3>& points, const Vec3& base);

// The part camera. The framing rule: seen from `view`, the projected bounding rectangle of the
// points is centred in the image and its larger relative side, max(box width / image width,
// box height / image height), equals `fill`; the whole path is therefore in the frame and spans at
// least `fill` of the image's smaller dimension. The eye stands max(kMinPartDistance,
// kPartDistancePerDiagonal x the points' bounding-box diagonal) from the box centre (so the arm's
// wrist above the part does not crowd the lens) and the field of view is chosen to meet the rule,
// the distance shortened where that would need a field of view below kMinFovyDeg (a part smaller
// than a few centimetres). `aspect` = image width / height. Fewer than two distinct points: the
// rule cannot apply and the camera looks at the point from kMinPartDistance with a 45 degree view.
struct PartFraming {
  double fill = 0.6;  // in (0, 1]
  std::optional<double> azimuth_deg, elevation_deg;  // override default_view's angles
};
inline constexpr double kMinPartDistance = 0.6;  // m
inline constexpr double kPartDistancePerDiagonal = 1.6;
inline constexpr double kMinFovyDeg = 4;
inline constexpr double kMaxFovyDeg = 90;
CameraPose frame_part(const std::vector<Vec3>& points, const Vec3& base, double aspect, const PartFraming& framing);

// The larger relative side of the points' projected bounding rectangle (the framing rule's
// share): max(box width / width, box height / height); 0 for fewer than two points. Points
// behind the eye are skipped.
double framed_share(const CameraPose& camera, const std::vector<Vec3>& points, int width, int height);

}  // namespace blendbench
