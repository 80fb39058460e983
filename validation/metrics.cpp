// Placeholder until the metrics land: no metrics yet.
#include "validation/metrics.h"

namespace pbdval {

MetricSet computeMetrics(const MetricInputs& /*inputs*/) {
  return {};
}

}  // namespace pbdval
