#include "viewer/view_tweaks.h"

namespace zz {

void apply_tweaks(const ViewTweaks& tweaks, RenderSettings& settings) {
  settings.adaptive.eps = tweaks.eps;
  settings.adaptive.filter = tweaks.mitchell ? Filter::Mitchell : Filter::Box;
  // `edges` is honoured by the viewer itself: it decides whether a visibility map is
  // built for the frame (no map = the sampler sees no geo flags).
}

}  // namespace zz
