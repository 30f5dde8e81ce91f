#include "step_first_pass.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <unordered_map>
#include <vector>

namespace vaw::step {
namespace {

// "1e12", "1e100": as a person writes a limit.
std::string number(double v) {
  std::ostringstream o;
  o << v;
  std::string s = o.str();
  if (const std::size_t e = s.find("e+"); e != std::string::npos) s.erase(e + 1, 1);
  return s;
}

std::string count(double v) {
  if (!std::isfinite(v) || v >= 1e15) return "more than 1e15";
  std::ostringstream o;
  o.precision(0);
  o << std::fixed << v;
  return o.str();
}

bool keywordChar(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '!';
}

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u)
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  return u;
}

// What the instance count needs of the assembly structure: the entity's top-level parameters, kept only
// for the four entity types that link an instance to its product's name.
struct Kept {
  std::string type;
  std::vector<std::string_view> params;
};

class Pass {
 public:
  Pass(std::string_view text, const FirstPassLimits& limits) : t_(text), limits_(limits) {}

  FirstPassResult run() {
    while (true) {
      skipSpace();
      if (i_ >= t_.size()) break;
      if (t_[i_] == '#') entity();
      else skipStatement();
    }
    if (result_.rewritten > 0) result_.text.append(t_.substr(copied_));
    countInstances();
    return std::move(result_);
  }

 private:
  [[noreturn]] void refuse(std::string field, std::string expected, std::string found) const {
    throw FirstPassRefusal{std::move(field), std::move(expected), std::move(found)};
  }

  std::size_t lineOf(std::size_t at) const {
    return 1 + static_cast<std::size_t>(std::count(t_.begin(), t_.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  }

  // Skips white space and comments; true when a line break or a comment was among them.
  bool skipSpace() {
    bool notable = false;
    while (i_ < t_.size()) {
      const char c = t_[i_];
      if (c == '\n' || c == '\r') {
        notable = true;
        ++i_;
      } else if (c == ' ' || c == '\t' || c == '\f' || c == '\v') {
        ++i_;
      } else if (c == '/' && i_ + 1 < t_.size() && t_[i_ + 1] == '*') {
        const std::size_t end = t_.find("*/", i_ + 2);
        i_ = end == std::string_view::npos ? t_.size() : end + 2;
        notable = true;
      } else {
        break;
      }
    }
    return notable;
  }

  void skipString(char quote) {
    ++i_;
    while (i_ < t_.size()) {
      if (t_[i_] == quote) {
        // '' inside a string is one quote.
        if (quote == '\'' && i_ + 1 < t_.size() && t_[i_ + 1] == '\'') {
          i_ += 2;
          continue;
        }
        ++i_;
        return;
      }
      ++i_;
    }
  }

  // A header statement or anything else that is not an entity instance: up to its ';'.
  void skipStatement() {
    while (i_ < t_.size()) {
      const char c = t_[i_];
      if (c == '\'' || c == '"') skipString(c);
      else if (c == '/' && i_ + 1 < t_.size() && t_[i_ + 1] == '*') skipSpace();
      else if (c == ';') {
        ++i_;
        return;
      } else {
        ++i_;
      }
    }
  }

  void entity() {
    const std::size_t hash = i_++;
    const std::size_t digits = i_;
    while (i_ < t_.size() && t_[i_] >= '0' && t_[i_] <= '9') ++i_;
    const std::string_view id = t_.substr(hash, i_ - hash);
    if (i_ == digits) return skipStatement();
    const std::size_t gap = i_;
    const bool notable = skipSpace();
    if (i_ >= t_.size() || t_[i_] != '=') return skipStatement();
    if (notable) {
      // Valid Part 21 that Open CASCADE 7.6 dies on: "#12 /* c */ =" and "#12<newline>=". Written as
      // "#12 =", the line breaks moved before the "#" so that every line keeps its number.
      result_.text.append(t_.substr(copied_, hash - copied_));
      result_.text.append(static_cast<std::size_t>(std::count(t_.begin() + static_cast<std::ptrdiff_t>(gap),
                                                              t_.begin() + static_cast<std::ptrdiff_t>(i_), '\n')),
                          '\n');
      result_.text.append(id);
      result_.text.append(" ");
      copied_ = i_;
      ++result_.rewritten;
    }
    ++i_;
    ++result_.entities;
    body(hash, id);
  }

  void body(std::size_t start, std::string_view id) {
    skipSpace();
    std::string type;
    if (i_ < t_.size() && t_[i_] != '(') {
      const std::size_t k = i_;
      while (i_ < t_.size() && keywordChar(t_[i_])) ++i_;
      type = upper(t_.substr(k, i_ - k));
    } else {
      type = "(complex entity)";
    }
    const bool point = type == "CARTESIAN_POINT";
    const bool keep = type == "NEXT_ASSEMBLY_USAGE_OCCURRENCE" || type == "PRODUCT_DEFINITION" ||
                      type.rfind("PRODUCT_DEFINITION_FORMATION", 0) == 0 || type == "PRODUCT";
    Kept kept;
    int depth = 0;
    bool paramStart = false;
    while (i_ < t_.size()) {
      const char c = t_[i_];
      if (c == ';' && depth <= 0) {
        ++i_;
        break;
      }
      if (c == '\'' || c == '"') {
        const std::size_t k = i_;
        skipString(c);
        if (keep && depth == 1 && paramStart) kept.params.push_back(t_.substr(k, i_ - k));
        paramStart = false;
        continue;
      }
      if (c == '/' && i_ + 1 < t_.size() && t_[i_ + 1] == '*') {
        skipSpace();
        continue;
      }
      if (c == '(') {
        if (keep && depth == 1 && paramStart) kept.params.push_back(t_.substr(i_, 1));
        ++depth;
        paramStart = true;
        ++i_;
        continue;
      }
      if (c == ')') {
        --depth;
        paramStart = false;
        ++i_;
        continue;
      }
      if (c == ',') {
        paramStart = true;
        ++i_;
        continue;
      }
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
        ++i_;
        continue;
      }
      const std::size_t k = i_;
      if ((c >= '0' && c <= '9') || c == '+' || c == '-' || (c == '.' && i_ + 1 < t_.size() && t_[i_ + 1] >= '0' && t_[i_ + 1] <= '9')) {
        while (i_ < t_.size() && ((t_[i_] >= '0' && t_[i_] <= '9') || t_[i_] == '.' || t_[i_] == 'E' || t_[i_] == 'e' ||
                                  t_[i_] == '+' || t_[i_] == '-'))
          ++i_;
        checkNumber(t_.substr(k, i_ - k), start, id, type, point);
      } else if (c == '.' ) {
        // An enumeration or logical: .T., .UNSPECIFIED.
        ++i_;
        while (i_ < t_.size() && keywordChar(t_[i_])) ++i_;
        if (i_ < t_.size() && t_[i_] == '.') ++i_;
      } else if (c == '#') {
        ++i_;
        while (i_ < t_.size() && t_[i_] >= '0' && t_[i_] <= '9') ++i_;
      } else if (keywordChar(c)) {
        while (i_ < t_.size() && keywordChar(t_[i_])) ++i_;
        const std::string word = upper(t_.substr(k, i_ - k));
        std::size_t after = i_;
        while (after < t_.size() && (t_[after] == ' ' || t_[after] == '\t' || t_[after] == '\n' || t_[after] == '\r')) ++after;
        // A typed parameter, LENGTH_MEASURE(2.), is followed by "("; a bare word where a value belongs is
        // what writers that print doubles with printf("%g") leave for NaN and infinity.
        if ((after >= t_.size() || t_[after] != '(') &&
            (word == "NAN" || word == "INF" || word == "INFINITY" || word == "-NAN" || word == "-INF"))
          refuse(std::string(id) + " " + type, "finite numbers (Part 21 has no NaN or infinity)",
                 "\"" + std::string(t_.substr(k, i_ - k)) + "\" on line " + std::to_string(lineOf(k)));
      } else {
        ++i_;  // $, *, and anything Open CASCADE's parser will name
      }
      if (keep && depth == 1 && paramStart) kept.params.push_back(t_.substr(k, i_ - k));
      paramStart = false;
    }
    if (keep) {
      kept.type = std::move(type);
      kept_.emplace(id, std::move(kept));
    }
  }

  void checkNumber(std::string_view token, std::size_t start, std::string_view id, const std::string& type, bool point) const {
    std::string_view digits = token;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    // A malformed number is the parser's to name; only its size is checked here.
    if (ec == std::errc::invalid_argument) return;
    const auto where = [&] { return std::string(token) + " on line " + std::to_string(lineOf(start)); };
    if (ec == std::errc::result_out_of_range || !std::isfinite(v)) {
      // Out of range is also an underflow (1e-400), which is a harmless zero.
      const std::size_t e = digits.find_first_of("eE");
      if (e != std::string_view::npos && digits.substr(e + 1).starts_with('-')) return;
      refuse(std::string(id) + " " + type, "finite numbers within ±" + number(limits_.maxNumber), where());
    }
    if (point && std::abs(v) > limits_.maxCoordinate)
      refuse(std::string(id) + " " + type,
             "coordinates within ±" + number(limits_.maxCoordinate) + " of the file's length unit", where());
    if (std::abs(v) > limits_.maxNumber)
      refuse(std::string(id) + " " + type,
             "numbers within ±" + number(limits_.maxNumber) + " (Open CASCADE takes larger ones for infinity)", where());
  }

  // Expands the tree of NEXT_ASSEMBLY_USAGE_OCCURRENCEs: each product definition's instances are the sum,
  // over the assemblies that use it, of their instances (a root has one).
  void countInstances() {
    std::unordered_map<std::string_view, std::vector<std::string_view>> children;
    std::unordered_map<std::string_view, int> usedBy;
    for (const auto& [id, k] : kept_) {
      if (k.type != "NEXT_ASSEMBLY_USAGE_OCCURRENCE" || k.params.size() < 5) continue;
      const std::string_view parent = k.params[3], child = k.params[4];
      if (parent.empty() || child.empty() || parent.front() != '#' || child.front() != '#') continue;
      children[parent].push_back(child);
      ++usedBy[child];
      (void)usedBy[parent];
    }
    if (children.empty()) return;

    // Depth-first post-order from the roots. A product that contains itself is refused here: skipping the
    // count there would let a file past the instance limit, and no CAD system writes one.
    enum class Mark : std::uint8_t { None, Open, Done };
    std::unordered_map<std::string_view, Mark> mark;
    std::vector<std::string_view> order;
    const auto containsItself = [&](std::string_view node, const std::string& through) {
      refuse(std::string(node) + " PRODUCT_DEFINITION", "an assembly tree, in which no product contains itself",
             productName(node) + " contains itself" + through);
    };
    for (const auto& [node, n] : usedBy) {
      if (n != 0) continue;
      std::vector<std::pair<std::string_view, std::size_t>> stack{{node, 0}};
      mark[node] = Mark::Open;
      while (!stack.empty()) {
        auto& [at, next] = stack.back();
        const auto c = children.find(at);
        if (c != children.end() && next < c->second.size()) {
          const std::string_view child = c->second[next++];
          Mark& m = mark[child];
          if (m == Mark::Open) {
            std::string through;
            for (auto it = std::find_if(stack.begin(), stack.end(), [&](const auto& e) { return e.first == child; }) + 1; it != stack.end(); ++it)
              through += (through.empty() ? " through " : ", ") + productName(it->first);
            containsItself(child, through);
          }
          if (m == Mark::None) {
            m = Mark::Open;
            stack.emplace_back(child, 0);
          }
        } else {
          mark[at] = Mark::Done;
          order.push_back(at);
          stack.pop_back();
        }
      }
    }
    // Products that no root reaches yet others contain: a cycle with nothing above it.
    for (const auto& [node, kids] : children)
      if (mark[node] == Mark::None) containsItself(node, " (a cycle no root reaches)");
    std::unordered_map<std::string_view, double> instances;
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
      double& mine = instances[*it];
      if (usedBy[*it] == 0) mine = 1.0;
      const auto c = children.find(*it);
      if (c == children.end()) continue;
      for (const std::string_view child : c->second) instances[child] += mine;
    }
    double total = 0.0, most = 0.0;
    std::string_view mostOf;
    for (const auto& [node, n] : instances) {
      if (children.count(node) != 0) continue;
      total += n;
      if (n > most) {
        most = n;
        mostOf = node;
      }
    }
    result_.instances = total;
    if (total > limits_.maxInstances)
      refuse(std::string(mostOf) + " PRODUCT_DEFINITION",
             "at most " + count(limits_.maxInstances) + " part instances (vaw-sim --max-instances, File > STEP Settings)",
             "an assembly of " + count(total) + " part instances, " + count(most) + " of them of " + productName(mostOf));
  }

  std::string productName(std::string_view definition) const {
    const auto param = [&](std::string_view id, std::size_t n) -> std::string_view {
      const auto k = kept_.find(id);
      return k == kept_.end() || k->second.params.size() <= n ? std::string_view() : k->second.params[n];
    };
    const std::string_view formation = param(definition, 2);
    const std::string_view product = param(formation, 2);
    std::string_view name = param(product, 1);
    if (name.size() >= 2 && name.front() == '\'') name = name.substr(1, name.size() - 2);
    if (name.empty()) return "the product defined by " + std::string(definition);
    return "\"" + std::string(name) + "\" (" + std::string(product) + ")";
  }

  std::string_view t_;
  const FirstPassLimits& limits_;
  std::size_t i_ = 0;
  std::size_t copied_ = 0;
  FirstPassResult result_;
  std::unordered_map<std::string_view, Kept> kept_;
};

}  // namespace

FirstPassResult firstPass(std::string_view text, const FirstPassLimits& limits) { return Pass(text, limits).run(); }

}  // namespace vaw::step
