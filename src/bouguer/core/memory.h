#pragma once
// Memory a piece of work may still take, so that a render that cannot fit is refused before it
// allocates, with one line naming the amount, instead of dying as std::bad_alloc.
#include <cstdint>
#include <string>
#include <string_view>

namespace bouguer {

// What this process can still allocate: the least of the memory the kernel reports available
// (MemAvailable) and what the address-space and data limits (ulimit -v, -d) leave.
std::uint64_t memory_available_bytes();

// Throws bouguer::Error ("WHAT needs about 22.5 GiB of memory; 9.1 GiB is available") when `bytes`
// exceed `available` (a caller that checks a growing estimate reads it once, before it allocates).
void require_memory(std::uint64_t bytes, std::string_view what, std::uint64_t available = memory_available_bytes());

// "22.5 GiB", "310 MiB", "12 KiB": for messages.
std::string format_bytes(std::uint64_t bytes);

}  // namespace bouguer
