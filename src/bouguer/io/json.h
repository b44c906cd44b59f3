#pragma once
// JSON as Bouguer reads it from a user's file: nlohmann's parser, with the rules of a hostile-input
// reader on top (docs/limits.md). A duplicated key is an error (nlohmann keeps the last one
// silently), a number beyond double's range says so with its line and column (nlohmann throws a
// bare out_of_range), nesting is bounded, and every message is one short line naming the file.
#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

namespace bouguer {

inline constexpr std::size_t kMaxJsonDepth = 64;  // the scene format nests 6 deep at most

// The document in `text`, read from `file` (named in messages as file:line:column: ...).
// Throws bouguer::Error.
nlohmann::json parse_json(std::string_view text, const std::filesystem::path& file);

// "line:column" of a byte offset, both counted from 1 (columns in bytes).
std::string line_and_column(std::string_view text, std::size_t offset);

}  // namespace bouguer
