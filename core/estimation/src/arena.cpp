#include "syrof/estimation/arena.h"

#include "syrof/base/check.h"

namespace syrof::estimation {

template <typename Scalar>
Vector3<Scalar> FourAnchorLayout<Scalar>::anchor(int i) const {
  switch (i) {
    case 0: return Vector3<Scalar>(0, 0, 0);
    case 1: return Vector3<Scalar>(side_m, side_m, 0);
    case 2: return Vector3<Scalar>(0, side_m, height_m);
    case 3: return Vector3<Scalar>(side_m, 0, height_m);
    default: break;
  }
  SYROF_CHECK(false && "the layout has anchors 0 .. 3");
  return Vector3<Scalar>::Zero();
}

template <typename Scalar>
FourAnchorLayout<Scalar> DefaultAnchorLayout() {
  return FourAnchorLayout<Scalar>{4, 2};
}

template <typename Scalar>
Arena<Scalar> ArenaFromLayout(const FourAnchorLayout<Scalar>& layout, Scalar tag_height_m) {
  Arena<Scalar> arena;
  arena.width_m = layout.side_m;
  arena.depth_m = layout.side_m;
  arena.tag_height_m = tag_height_m;
  arena.anchor_count = 4;
  for (int i = 0; i < kMaxAnchors; ++i) arena.anchors[i] = i < 4 ? layout.anchor(i) : Vector3<Scalar>::Zero();
  return arena;
}

template <typename Scalar>
Arena<Scalar> DefaultArena() {
  return ArenaFromLayout(DefaultAnchorLayout<Scalar>(), static_cast<Scalar>(0.10));
}

template struct FourAnchorLayout<float>;
template struct FourAnchorLayout<double>;
template FourAnchorLayout<float> DefaultAnchorLayout<float>();
template FourAnchorLayout<double> DefaultAnchorLayout<double>();
template Arena<float> ArenaFromLayout<float>(const FourAnchorLayout<float>&, float);
template Arena<double> ArenaFromLayout<double>(const FourAnchorLayout<double>&, double);
template Arena<float> DefaultArena<float>();
template Arena<double> DefaultArena<double>();

}  // namespace syrof::estimation
