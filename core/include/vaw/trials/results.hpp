#pragma once
// The results file: JSON Lines, append-only. Line 1 is a header carrying the design the session ran;
// each further line is one answered trial, written whole and synced before the next trial starts
// (docs/trials.md, "Results and crash safety").
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "vaw/trials/trial.hpp"

namespace vaw::trials {

inline constexpr int kResultsFormatVersion = 1;

// A last record cut off mid-line (the process died inside its write): never part of the results.
struct TornTail {
  int line = 0;                // the line it started
  std::uintmax_t offset = 0;   // where it starts: the length of the whole records before it
  std::uintmax_t bytes = 0;    // how much of it there is
};

struct ResultsFile {
  std::filesystem::path path;
  Design design;
  std::vector<Record> records;
  std::optional<TornTail> torn;
};

// Reads a results file without changing it. Every record is checked against the design by replaying
// its method, so a record that the design could not have produced is an error, as is a malformed one;
// errors name the file, the line ("line 7.answer") and what was expected. A torn last record is
// reported in `torn` and left out.
ResultsFile readResults(const std::filesystem::path& file);

}  // namespace vaw::trials
