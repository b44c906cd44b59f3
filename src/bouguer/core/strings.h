#pragma once
// Name helpers for error messages.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bouguer {

// Levenshtein edit distance (case-sensitive).
std::size_t edit_distance(std::string_view a, std::string_view b);

// The candidate closest to `name`, when it is close enough to be a plausible misspelling
// (at most a third of the name's letters differ, and at least one edit is allowed).
std::optional<std::string> nearest_name(std::string_view name, const std::vector<std::string>& candidates);

// The tail of an "unknown name" message: " (did you mean 'x'?)" for a plausible misspelling,
// otherwise " (known: a, b, c)".
std::string suggestion(std::string_view name, const std::vector<std::string>& candidates);

// RFC 4648 base64 (for data: URIs in self-contained pages).
std::string base64_encode(std::string_view bytes);

}  // namespace bouguer
