// vaw-step-import, first stage: the Part 21 header, checked before anything reads the DATA section
// (step_reader.hpp). Progress goes to stdout for the plugin.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <string>
#include <vector>

#include "step_reader.hpp"

namespace vaw::step::reader {

void progress(double fraction, const std::string& stage) {
  std::printf("progress %.3f %s\n", fraction, stage.c_str());
  std::fflush(stdout);
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// ---------------------------------------------------------------------------------------------------
// The Part 21 header, checked before OCCT sees the file: OCCT ignores FILE_SCHEMA (an IFC file loads as
// AP214) and says nothing useful about a file cut short.

std::string checkHeader(const std::string& text) {
  const std::string head = text.substr(0, 256 * 1024);
  if (head.rfind("\xEF\xBB\xBF", 0) == 0)
    throw BadFile{"", "a STEP file starting with ISO-10303-21;",
                  "a UTF-8 byte-order mark first (Open CASCADE refuses it; remove the first 3 bytes)"};
  std::size_t start = 0;
  while (start < head.size() && std::isspace(static_cast<unsigned char>(head[start]))) ++start;
  if (head.compare(start, 13, "ISO-10303-21;") != 0)
    throw BadFile{"", "a STEP file (ISO 10303-21)", "not a STEP file: no ISO-10303-21 header"};

  const std::string up = upper(head);
  const std::size_t schemaAt = up.find("FILE_SCHEMA");
  const std::size_t dataAt = up.find("DATA;");
  if (schemaAt == std::string::npos || (dataAt != std::string::npos && schemaAt > dataAt))
    throw BadFile{"HEADER.FILE_SCHEMA", "a FILE_SCHEMA of AP203, AP214 or AP242", "no FILE_SCHEMA in the header"};
  const std::size_t schemaEnd = up.find(';', schemaAt);
  const std::string schemaText = up.substr(schemaAt, schemaEnd == std::string::npos ? 400 : schemaEnd - schemaAt);
  std::vector<std::string> names;
  for (std::size_t q = schemaText.find('\''); q != std::string::npos;) {
    const std::size_t e = schemaText.find('\'', q + 1);
    if (e == std::string::npos) break;
    names.push_back(schemaText.substr(q + 1, e - q - 1));
    q = schemaText.find('\'', e + 1);
  }
  std::string format;
  for (const std::string& raw : names) {
    // "AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }": the name is the first word.
    const std::string name = raw.substr(0, raw.find_first_of(" {"));
    if (name.rfind("CONFIG_CONTROL_DESIGN", 0) == 0 || name.rfind("AP203", 0) == 0) format = "STEP AP203";
    else if (name.rfind("AUTOMOTIVE_DESIGN", 0) == 0 || name.rfind("AP214", 0) == 0) format = "STEP AP214";
    else if (name.rfind("AP242", 0) == 0) format = "STEP AP242";
    if (!format.empty()) break;
  }
  if (format.empty()) {
    std::string found = names.empty() ? std::string("an empty FILE_SCHEMA") : "unsupported schema \"" + names.front() + "\"";
    throw BadFile{"HEADER.FILE_SCHEMA",
                  "CONFIG_CONTROL_DESIGN (AP203), AUTOMOTIVE_DESIGN (AP214) or AP242_MANAGED_MODEL_BASED_3D_ENGINEERING (AP242)",
                  found};
  }

  // A file cut short (an interrupted download or copy) lacks the closing keyword.
  const std::size_t size = text.size();
  std::string tail = text.substr(size - std::min<std::size_t>(size, 4096));
  while (!tail.empty() && std::isspace(static_cast<unsigned char>(tail.back()))) tail.pop_back();
  if (upper(tail).size() < 17 || upper(tail).compare(tail.size() - 17, 17, "END-ISO-10303-21;") != 0) {
    const bool inData = up.find("DATA;") != std::string::npos && upper(tail).rfind("ENDSEC;") == std::string::npos;
    throw BadFile{"", "a complete STEP file ending with END-ISO-10303-21;",
                  std::string("truncated: the file ends after ") + std::to_string(size) + " bytes" +
                      (inData ? ", inside the DATA section" : "") + " without END-ISO-10303-21;"};
  }
  return format;
}

}  // namespace vaw::step::reader
