#pragma once
// Writes go to a temporary file in the target's folder and are renamed into place only when the
// writer finished: a failed or interrupted run never leaves a half-written file, and an earlier
// file of the same name survives any failure.
#include <filesystem>
#include <functional>
#include <string_view>

namespace bouguer {

// Calls write(temp_path); on success renames temp_path to target, on any exception removes
// temp_path and rethrows. Errors (folder missing, rename refused) name the target.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path& temp_path)>& write);

// A fresh temporary name beside target that keeps its extension ("dir/a.png" ->
// "dir/.a.tmp-<pid>-<n>.png"), so writers that choose the format by extension accept it.
std::filesystem::path temporary_path_for(const std::filesystem::path& target);

// Writes bytes already in memory (an encoded image, a page, JSON) the same way.
void write_bytes_atomically(const std::filesystem::path& target, std::string_view bytes);

}  // namespace bouguer
