#pragma once
// Pyramidal Lucas-Kanade optical flow (Bouguet's formulation), for checking that a synthesized
// texture moves with the fluid (Gagnon et al. 2021, Fig. 16). Written for the tests: OpenCV is
// not a dependency of texsim.
#include <vector>

namespace texsim::test {

/// A grey image, row-major, row 0 at the top.
struct GreyPicture {
  int width = 0, height = 0;
  std::vector<float> values;
  float at(int x, int y) const {
    return values[std::size_t(y) * std::size_t(width) + std::size_t(x)];
  }
};

/// The flow of one pixel: where its neighbourhood of `first` went in `second`, in pixels (x right,
/// y down), and whether the window had enough texture to say (smallest eigenvalue of the
/// structure tensor, per pixel of the window, above a threshold).
struct FlowVector {
  double dx = 0, dy = 0;
  bool valid = false;
};

/// Flow at pixel (x, y) of `first` towards `second`: `levels` pyramid levels (2x2 box reduction),
/// a (2 half_window + 1)^2 window, up to 20 Newton iterations per level.
FlowVector lucas_kanade(const GreyPicture& first, const GreyPicture& second, int x, int y,
                        int levels = 3, int half_window = 4);

/// The same for many pixels, sharing the pyramids.
class LucasKanade {
public:
  LucasKanade(const GreyPicture& first, const GreyPicture& second, int levels = 3,
              int half_window = 4);
  FlowVector at(int x, int y) const;

private:
  std::vector<GreyPicture> first_, second_;
  int half_window_;
};

} // namespace texsim::test
