#include "viewer/view_tweaks.h"

namespace zz {

void apply_tweaks(const ViewTweaks& tweaks, RenderSettings& settings) {
  settings.adaptive.eps = tweaks.eps;
  settings.adaptive.filter = tweaks.mitchell ? Filter::Mitchell : Filter::Box;
  // `edges` also decides, in the viewer itself, whether a visibility map is built for the
  // frame (no map = the sampler sees no geo flags).
  settings.adaptive.map_crease = tweaks.edges ? tweaks.map_crease : 0.0f;
}

}  // namespace zz
