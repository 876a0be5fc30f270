// Where the UWB anchors are, and at what height the robots' antennas move.
//
// The paper places four anchors at the corners of a unit cube, alternating
// between floor and ceiling: (0,0,0), (1,1,0), (0,1,1), (1,0,1). The default
// arena keeps that pattern on a 4 m square with the upper pair at 2 m:
//   a0 = (0,0,0), a1 = (4,4,0), a2 = (0,4,2), a3 = (4,0,2),
// and the antennas at 0.10 m. Why 2 m and not the scaled cube's 4 m: a range
// constrains x and y by the horizontal share of its direction, which shrinks
// as an anchor rises above the antennas. Over the arena's inner 3 m square the
// horizontal dilution of precision of the four ranges is 1.11 (median) and
// 1.18 (worst) with the upper pair at 2 m, against 1.34 and 1.47 at 4 m; 2 m
// is also a height a tripod reaches. The height difference still gives the
// closed form and 3-D least squares a usable z. docs/estimation.md has the
// table.
#pragma once

#include "syrof/estimation/messages.h"
#include "syrof/estimation/state.h"

namespace syrof::estimation {

/// The paper's four-anchor layout scaled: a0 = (0, 0, 0), a1 = (L, L, 0),
/// a2 = (0, L, h), a3 = (L, 0, h), with L = side_m and h = height_m (the
/// paper's unit cube is L = h = 1).
template <typename Scalar>
struct FourAnchorLayout {
  Scalar side_m = 1;
  Scalar height_m = 1;

  /// Anchor i (0 .. 3) of the layout.
  Vector3<Scalar> anchor(int i) const;
};

/// An arena: its floor extent, its anchors (in the order UWB readings use)
/// and the height of the plane the robots' antennas move on.
template <typename Scalar>
struct Arena {
  Scalar width_m = 0;       ///< floor spans x in [0, width_m]
  Scalar depth_m = 0;       ///< and y in [0, depth_m]
  Scalar tag_height_m = 0;  ///< z of every robot's UWB antenna
  int anchor_count = 0;     ///< 0 .. kMaxAnchors
  /// Anchor positions, m; entries from anchor_count on are not used (Eigen
  /// leaves a default-constructed vector uninitialized: set what you use).
  Vector3<Scalar> anchors[kMaxAnchors];
};

/// The default arena's layout: FourAnchorLayout{4, 2}.
template <typename Scalar>
FourAnchorLayout<Scalar> DefaultAnchorLayout();

/// An arena of side layout.side_m with the layout's four anchors.
template <typename Scalar>
Arena<Scalar> ArenaFromLayout(const FourAnchorLayout<Scalar>& layout, Scalar tag_height_m);

/// The default arena: 4 m x 4 m, DefaultAnchorLayout(), antennas at 0.10 m.
template <typename Scalar>
Arena<Scalar> DefaultArena();

}  // namespace syrof::estimation
