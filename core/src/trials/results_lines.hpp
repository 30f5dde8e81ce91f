#pragma once
// The results file's lines, shared by the reader and the runner that appends them.
#include <string>

#include "vaw/trials/procedure.hpp"
#include "vaw/trials/results.hpp"

namespace vaw::trials::detail {

std::string headerLine(const Design& d);   // ends in '\n'
std::string recordLine(const Record& r);   // ends in '\n'

struct Parsed {
  ResultsFile file;
  Procedure procedure;  // replayed through every whole record
};

// Parses the text of a results file. A text without one whole line has no header: an InputError.
Parsed parseResults(const std::string& text, const std::filesystem::path& file);

}  // namespace vaw::trials::detail
