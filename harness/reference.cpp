#include "harness/reference.h"

#include <algorithm>
#include <stdexcept>

namespace sb {

ReferenceWindow::ReferenceWindow(const DepthSource& source, int64_t x0, int64_t y0, int64_t w,
                                 int64_t h) {
  const int64_t r = source.resolution(), pw = DepthSource::kPacketWidth,
                ph = DepthSource::kPacketHeight;
  x0_ = std::clamp<int64_t>(x0, 0, r) / pw * pw;
  y0_ = std::clamp<int64_t>(y0, 0, r) / ph * ph;
  x1_ = (std::clamp<int64_t>(x0 + w, 0, r) + pw - 1) / pw * pw;
  y1_ = (std::clamp<int64_t>(y0 + h, 0, r) + ph - 1) / ph * ph;
  intervals_.resize(size_t((x1_ - x0_) * (y1_ - y0_)));
  for (int64_t j0 = y0_; j0 < y1_; j0 += ph)
    for (int64_t i0 = x0_; i0 < x1_; i0 += pw) {
      const DepthSource::Packet packet = source.tracePacket(uint32_t(i0), uint32_t(j0));
      for (uint32_t lane = 0; lane < DepthSource::kPacketSize; ++lane)
        intervals_[size_t(j0 + lane / pw - y0_) * (x1_ - x0_) + (i0 + lane % pw - x0_)] =
            packet[lane];
    }
}

}  // namespace sb
