// Closed-form test solids: closed, outward-oriented indexed meshes with their exact sections.
//
// Every generator returns a Solid: the polygonal mesh (faces counter-clockwise seen from
// outside, vertices shared, no duplicates) together with closed forms for that *polygonal*
// shape, never for the smooth shape it approximates:
//   volume         exact volume of the mesh, mm^3
//   area(z)        exact area of the cross-section at height z, mm^2
//   perimeter(z)   exact length of all its loops (holes included), mm
//   section(z)     the exact cross-section as a Region: outer loops CCW, holes CW
// All three follow slicer.h's convention, the limit from above: C(z) = lim C(z + e), so a
// solid spanning [z0, z1] has its full bottom section at z0 and nothing at z1. A section that
// shrinks to a point or a segment (an apex, a ridge) is empty. Units are mm throughout.
//
// Solids of revolution use a regular n-gon: vertex i of every ring sits at angle
// phase + 2*pi*i/n around the axis. Between two ring heights every band is made of planar
// isosceles trapezoids, so the section there is a regular n-gon whose circumradius varies
// linearly with z; its area is regular_polygon_area(n, r) = n/2 r^2 sin(2 pi/n) and its
// perimeter regular_polygon_perimeter(n, r) = 2 n r sin(pi/n). Triangulation diagonals add
// collinear points to a slice, which change neither area nor perimeter.
//
// Unless stated otherwise a solid stands on z = 0 centred on the z axis. Sizes must be
// positive and polygon counts >= 3; nothing here validates its arguments (it is test code).
#pragma once

#include <functional>
#include <vector>

#include "geometry/mesh/mesh.h"
#include "geometry/core/polygon.h"

namespace solids {

struct Solid {
  geometry::Mesh mesh;
  double volume = 0;
  std::function<double(double z)> area;
  std::function<double(double z)> perimeter;
  std::function<geometry::Region(double z)> section;
};

// A regular n-gon, counter-clockwise, vertex i at centre + r (cos a_i, sin a_i),
// a_i = phase + 2 pi i / n.
geometry::Loop regular_polygon(int n, double circumradius, geometry::Vec2 centre = {},
                               double phase = 0);
double regular_polygon_area(int n, double circumradius);
double regular_polygon_perimeter(int n, double circumradius);

// Axis-aligned box [min, max]. Section: the rectangle for min.z <= z < max.z.
Solid box(geometry::Vec3 min, geometry::Vec3 max);

// The cube [0, side]^3 (the example of slicer.h).
Solid cube(double side);

// The general solid of revolution about the vertical axis through `axis`: `profile` is a
// simple polygon in the (rho, z) half-plane, rho >= 0, counter-clockwise with rho as the
// first coordinate (so for a cylinder: (0,0), (r,0), (r,h), (0,h)). Profile vertices with
// rho == 0 become single vertices on the axis (poles, cap centres); profile edges along the
// axis are not surface. Section at z: the profile's crossings rho_0 < rho_1 < ... by the line
// at z (limit from above) pair into intervals [rho_2k, rho_2k+1], each an n-gon ring
// (outer rho_2k+1 CCW, inner rho_2k CW unless it is 0). Intervals that touch are merged (the
// slit between them has zero width) and empty ones dropped.
// Volume: n/2 sin(2 pi/n) * sum over profile edges (z_b - z_a)(r_a^2 + r_a r_b + r_b^2)/3.
Solid revolve(const std::vector<geometry::Vec2>& profile, int n, geometry::Vec2 axis = {},
              double phase = 0);

// n-gon prism, circumradius `radius`, from base.z to base.z + height, axis through base.
Solid cylinder(double radius, double height, int n, geometry::Vec3 base = {});

// Hollow n-gon tube: circumradii inner < outer. Section: one CCW outer, one CW hole.
Solid tube(double inner_radius, double outer_radius, double height, int n,
           geometry::Vec3 base = {});

// n-gon frustum: circumradius r_bottom at base.z, r_top at base.z + height (either may be 0).
Solid frustum(double r_bottom, double r_top, double height, int n, geometry::Vec3 base = {});

// n-gon cone: apex at base.z + height. Section at z: n-gon of radius radius (1 - (z-z0)/h).
Solid cone(double radius, double height, int n, geometry::Vec3 base = {});

// UV sphere: `segments` vertices per ring, `rings` latitude bands (rings - 1 vertex rings
// at polar angles pi k / rings, k = 1 .. rings-1, plus the two poles). Ring k lies at
// z = centre.z + R cos(pi k / rings) with circumradius R sin(pi k / rings); between two
// ring heights the section is an n-gon whose circumradius is linear in z.
Solid sphere(double radius, int segments, int rings, geometry::Vec3 centre = {});

// Torus about the vertical axis through `centre`: its tube is the m-gon of circumradius
// `minor` around (rho, z) = (major, centre.z), tube vertex j at angle 2 pi j / m (j = 0 on
// the outer equator), revolved with `segments` = n. Needs minor < major. Section between the
// tube's lowest and highest vertex: an annulus of two n-gons (outer CCW, hole CW).
Solid torus(double major, double minor, int segments, int tube_segments,
            geometry::Vec3 centre = {});

// Double n-gon pyramid: apexes at z_bottom and z_top on the axis, the n equator vertices
// (circumradius `radius`) all exactly at z_equator. A plane at z_equator meets vertices only.
Solid bipyramid(double radius, int n, double z_bottom, double z_equator, double z_top,
                geometry::Vec2 axis = {});

// The cube [-side/2, side/2]^2 x [0, side] with a vertical through hole: `hole` is a convex,
// counter-clockwise polygon strictly inside the square that contains the origin. Section for
// 0 <= z < side: the square (CCW) and the hole (CW); area side^2 - area(hole), perimeter
// 4 side + perimeter(hole).
Solid cube_with_hole(double side, const geometry::Loop& hole);
// ... with the axis-aligned square hole [-hole_side/2, hole_side/2]^2.
Solid cube_with_square_hole(double side, double hole_side);
// ... with the regular n-gon hole regular_polygon(n, hole_radius).
Solid cube_with_round_hole(double side, double hole_radius, int n);

// Two stacked boxes, both centred on the z axis: lower_size.x x lower_size.y from z = 0 to
// lower_height, upper_size from lower_height to lower_height + upper_height. One footprint must
// contain the other strictly in both directions (the upper may overhang). The step face lies
// exactly on z = lower_height: there the section is the upper box's rectangle.
Solid stepped_box(geometry::Vec2 lower_size, double lower_height, geometry::Vec2 upper_size,
                  double upper_height);

// A simple polygon in the (y, z) plane, counter-clockwise with y first, extruded along x from
// x0 to x1 (a prism lying on its side; end caps by ear clipping). Section at z: one rectangle
// [x0, x1] x [y_2k, y_2k+1] per interval between the profile's crossings of z (touching
// intervals merged, as for revolve).
Solid lying_prism(const std::vector<geometry::Vec2>& profile_yz, double x0, double x1);

// lying_prism of the rhombus (y, z) = (0, z_mid - half_height), (half_width, z_mid),
// (0, z_mid + half_height), (-half_width, z_mid), from x = -length/2 to length/2: its two
// horizontal side edges lie exactly on z = z_mid, where the section is length x 2 half_width.
Solid diamond_prism(double length, double half_width, double z_mid, double half_height);

// Disjoint union (the caller keeps the two apart, e.g. a cylinder inside a tube's hole):
// meshes concatenated, volumes, areas and perimeters added, sections' loops concatenated.
Solid combine(Solid a, Solid b);

}  // namespace solids
