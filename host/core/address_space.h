// The process's address-space limit (ulimit -v, RLIMIT_AS): the memory budget subtracts
// what is mapped from it, and the Vulkan errors name it, since lavapipe that cannot map
// its memory under one lists no device or fails to create it.
#pragma once

#include <cstdint>

namespace zz {

// The soft RLIMIT_AS in bytes; 0 when there is none (unlimited, or unreadable).
uint64_t address_space_limit();

}  // namespace zz
