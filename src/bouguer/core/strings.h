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

// Text from a file as an error message quotes it: at most `max_bytes` bytes, cut at a UTF-8
// boundary and marked "… (N bytes)" when longer, with control characters escaped (\n, \t, \xNN)
// so that the message stays one short line whatever the file holds. Every reader quotes through it.
std::string excerpt(std::string_view text, std::size_t max_bytes = 40);

// RFC 4648 base64 (for data: URIs in self-contained pages).
std::string base64_encode(std::string_view bytes);

}  // namespace bouguer
