// The STEP reader's first pass over a Part 21 file, before Open CASCADE sees it (docs/step.md, "Refused up
// front"). Open CASCADE spends minutes on a NaN coordinate or an assembly that declares tens of thousands
// of instances before failing, and crashes on two valid spellings; one linear pass over the text refuses
// the first with the entity named, in well under a second, and rewrites the second. It links no Open
// CASCADE, so the fuzzers and the sanitizer build run it alone.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace vaw::step {

struct FirstPassLimits {
  // In the file's own length unit. The reader refuses a part whose box goes past 1e12 mm anyway; a point
  // that far out is an exporter's garbage in any unit.
  double maxCoordinate = 1e12;
  // Any real. Open CASCADE takes 2e100 for infinity, so nothing larger is a measure.
  double maxNumber = 1e100;
  // Part instances once the assembly tree is expanded (every leaf product times the instances of every
  // assembly above it).
  double maxInstances = 10000;
};

// A file refused by the first pass; the fields of vaw::Diagnostic.
struct FirstPassRefusal {
  std::string field;
  std::string expected;
  std::string found;
};

struct FirstPassResult {
  // The text Open CASCADE should read when `rewritten` > 0; empty otherwise (read the file itself).
  std::string text;
  std::size_t rewritten = 0;  // spellings rewritten (a comment or a line break between "#id" and "=")
  std::size_t entities = 0;
  double instances = 0;  // part instances the assembly tree declares (0: no assembly structure)
};

// Throws FirstPassRefusal. Line numbers in the rewritten text are those of the original.
FirstPassResult firstPass(std::string_view text, const FirstPassLimits& limits = {});

}  // namespace vaw::step
