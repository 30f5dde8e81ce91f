// Every reference in the repository resolves: the documents' relative links (and their #anchors), and the
// file paths that comments and build files cite. The project documents itself: a reference to a file
// outside the repository, or to an issue tracker it does not have, fails here. Also the layering rule
// that the core never includes Qt.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path kRoot = VAW_SOURCE_DIR;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool hasExtension(const fs::path& p, std::initializer_list<const char*> exts) {
  const std::string e = p.extension().string();
  return std::any_of(exts.begin(), exts.end(), [&](const char* x) { return e == x; });
}

// The repository's own text files: not the build trees, not generated pictures.
std::vector<fs::path> sourceFiles() {
  std::vector<fs::path> out;
  for (auto it = fs::recursive_directory_iterator(kRoot); it != fs::recursive_directory_iterator(); ++it) {
    const std::string name = it->path().filename().string();
    if (it->is_directory() && (name.starts_with(".") || name.starts_with("build") || name == "out" || name == "__pycache__")) {
      it.disable_recursion_pending();
      continue;
    }
    if (!it->is_regular_file()) continue;
    if (hasExtension(it->path(), {".md", ".cpp", ".hpp", ".h", ".txt", ".sh", ".py", ".json", ".xml", ".desktop", ".dot"}) ||
        name == "run" || name == ".clang-format" || name == ".clang-tidy")
      out.push_back(it->path());
  }
  for (const char* hidden : {".ci/run", ".clang-format", ".clang-tidy"})
    if (fs::exists(kRoot / hidden)) out.push_back(kRoot / hidden);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::string inRepo(const fs::path& p) { return fs::relative(p, kRoot).string(); }

// Calls `f(line, number)` for each line of `file`, numbered from 1.
void forEachLine(const fs::path& file, const std::function<void(const std::string&, int)>& f) {
  std::istringstream in(read(file));
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) f(line, number);
}

// GitHub's heading anchors: lower case, punctuation other than '-' and '_' dropped, spaces as '-'.
std::set<std::string> anchors(const std::string& markdown) {
  std::set<std::string> out;
  std::istringstream in(markdown);
  std::string line;
  bool fenced = false;
  while (std::getline(in, line)) {
    if (line.starts_with("```")) fenced = !fenced;
    if (fenced || !line.starts_with("#")) continue;
    const std::string title = line.substr(line.find_first_not_of('#'));
    std::string slug;
    for (const char c : title) {
      const auto u = static_cast<unsigned char>(c);
      if (std::isalnum(u) || c == '-' || c == '_') slug += static_cast<char>(std::tolower(u));
      else if (c == ' ') slug += '-';
    }
    while (slug.starts_with("-")) slug.erase(0, 1);
    out.insert(slug);
  }
  return out;
}

// Inside the repository: a path that leaves it may exist beside this checkout, but a clone lacks it.
bool inside(const fs::path& p) {
  const std::string canonical = fs::weakly_canonical(p).string(), root = fs::weakly_canonical(kRoot).string();
  return canonical.starts_with(root + "/") && fs::exists(p);
}

// Where a path cited in a file may live: beside it, from the root, or under the core's include folder.
bool resolves(const fs::path& from, const std::string& target) {
  for (const fs::path& base :
       {from.parent_path(), from.parent_path().parent_path(), kRoot, kRoot / "core/include", kRoot / "core/include/vaw", kRoot / "core/src"})
    if (inside(base / target)) return true;
  return false;
}

}  // namespace

TEST(References, DocumentLinksResolve) {
  const std::regex link(R"(\]\(([^)\s]+)\))");
  std::vector<std::string> broken;
  std::size_t checked = 0;
  for (const auto& file : sourceFiles()) {
    if (file.extension() != ".md") continue;
    const std::string text = read(file);
    for (std::sregex_iterator m(text.begin(), text.end(), link), end; m != end; ++m) {
      const std::string target = (*m)[1];
      if (target.find("://") != std::string::npos || target.starts_with("mailto:")) continue;
      ++checked;
      const std::size_t hash = target.find('#');
      const std::string path = target.substr(0, hash), anchor = hash == std::string::npos ? "" : target.substr(hash + 1);
      const fs::path resolved = path.empty() ? file : file.parent_path() / path;
      if (!inside(resolved)) {
        broken.push_back(inRepo(file) + ": " + target + " (no such file)");
      } else if (!anchor.empty() && resolved.extension() == ".md" && !anchors(read(resolved)).contains(anchor)) {
        broken.push_back(inRepo(file) + ": " + target + " (no such heading)");
      }
    }
  }
  EXPECT_GT(checked, 30u) << "the documents link to each other";
  for (const auto& b : broken) ADD_FAILURE() << b;
}

TEST(References, CitedFilesExistInTheRepository) {
  // A path with a folder and a file extension (docs/physics.md, tests/sim/scripts/hoist-demo.vaw-inputs.json),
  // or any name ending in .md. Placeholders in capitals (DIR/session.json), build outputs (build/...),
  // absolute paths and paths inside an installed package (./usr/...) are not references to the
  // repository; nor are the examples in the documents' code blocks.
  const std::regex path(R"((?:^|[\s(`'"\[<,;=])((?:\.\./|\./)*(?:[A-Za-z0-9_.-]+/)+[A-Za-z0-9_.-]+\.(?:md|hpp|cpp|h|json|svg|png|dot|sh|py|csv|txt|xml|desktop|stl|obj|ply|gltf))(?=$|[\s)`'",.;:\]>]))");
  const std::regex markdownName(R"((?:^|[^A-Za-z0-9_./-])([A-Za-z0-9_-]+\.md)\b)");
  const std::regex include(R"(^\s*#\s*include\b)");
  std::vector<std::string> broken;
  std::size_t checked = 0;
  for (const auto& file : sourceFiles()) {
    bool fenced = false;
    forEachLine(file, [&](const std::string& line, int number) {
      if (file.extension() == ".md" && line.starts_with("```")) fenced = !fenced;
      if (fenced || std::regex_search(line, include)) return;  // examples; the compiler checks includes
      const auto check = [&](const std::string& target) {
        if (target.starts_with("build") || target.starts_with("/") || target.starts_with("./usr/")) return;
        const std::string first = target.substr(0, target.find('/'));
        if (std::all_of(first.begin(), first.end(), [](char c) { return std::isupper(static_cast<unsigned char>(c)) || c == '_'; }))
          return;
        ++checked;
        if (!resolves(file, target)) broken.push_back(inRepo(file) + ":" + std::to_string(number) + ": " + target);
      };
      for (std::sregex_iterator m(line.begin(), line.end(), path), end; m != end; ++m) check((*m)[1]);
      for (std::sregex_iterator m(line.begin(), line.end(), markdownName), end; m != end; ++m) check((*m)[1]);
    });
  }
  EXPECT_GT(checked, 50u) << "comments and documents cite files";
  for (const auto& b : broken) ADD_FAILURE() << "cites a file that is not in the repository: " << b;
}

TEST(References, NoIssueTrackerNumbers) {
  // The repository has no issue tracker: an issue number (or an issue's title in quotes) in a comment
  // leads nowhere.
  const std::regex issue(R"(\bissues?\s*(#?\s*[0-9]+|"))", std::regex::icase);
  for (const auto& file : sourceFiles())
    forEachLine(file, [&](const std::string& line, int number) {
      if (std::regex_search(line, issue)) ADD_FAILURE() << inRepo(file) << ":" << number << ": " << line;
    });
}

TEST(References, NoPathLeavesTheRepository) {
  // A relative path that climbs out of the repository (a checkout's sibling folder, a hooks path) exists
  // only on one machine. Paths built at run or install time ($ORIGIN/.., $(dirname "$0")/..) are not
  // references to files.
  const std::regex climb(R"((^|[\s(`'"\[<,;=])((?:\.\./)+[A-Za-z0-9_.-][A-Za-z0-9_./-]*))");
  const std::string root = fs::weakly_canonical(kRoot).string() + "/";
  std::size_t checked = 0;
  for (const auto& file : sourceFiles())
    forEachLine(file, [&](const std::string& line, int number) {
      for (std::sregex_iterator m(line.begin(), line.end(), climb), end; m != end; ++m) {
        ++checked;
        const fs::path target = fs::weakly_canonical(file.parent_path() / std::string((*m)[2]));
        if (!target.string().starts_with(root))
          ADD_FAILURE() << inRepo(file) << ":" << number << ": " << (*m)[2] << " leaves the repository";
      }
    });
  EXPECT_GT(checked, 10u) << "the bundled scenes cite their meshes as ../meshes/...";
}

TEST(Layering, TheCoreNeverIncludesQt) {
  const std::regex qt(R"(^\s*#\s*include\s*[<"](Q|Qt)[A-Za-z0-9]*[/>".])");
  for (const auto& file : sourceFiles()) {
    if (!inRepo(file).starts_with("core/")) continue;
    forEachLine(file, [&](const std::string& line, int number) {
      if (std::regex_search(line, qt)) ADD_FAILURE() << inRepo(file) << ":" << number << ": " << line;
    });
  }
}
