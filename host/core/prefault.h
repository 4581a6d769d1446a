// Mapping fresh memory in ahead of its first use, so the page faults of a large buffer are
// paid where the caller chooses (before a timed pass, beside other work), not inside it.
#pragma once

#include <cstddef>

namespace zz {

// Makes every page of [data, data + bytes) resident and writable. The contents are left
// undefined (zero on fresh anonymous pages, unchanged elsewhere).
void prefault(void* data, size_t bytes);

}  // namespace zz
