#include "vaw/report/report.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "picture.hpp"
#include "view3d.hpp"
#include "vaw/evaluation/way_clearance.hpp"
#include "vaw/atomic_file.hpp"
#include "vaw/error.hpp"

namespace vaw::report {

// The evaluation's plans, checks and sessions are what this page shows.
using namespace vaw::eval;

namespace {

using nlohmann::json;

std::string html(const std::string& s) {
  std::string o;
  for (const char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else if (c == '"') o += "&quot;";
    else o += c;
  }
  return o;
}

std::string csv(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string o = "\"";
  for (const char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

Eigen::Vector3f colorOf(const Assembly& a, PartId p) {
  if (a.parts[p].color) return *a.parts[p].color;
  static const Eigen::Vector3f palette[] = {{0.27f, 0.51f, 0.71f}, {0.85f, 0.55f, 0.2f}, {0.4f, 0.65f, 0.35f},
                                            {0.75f, 0.35f, 0.35f}, {0.55f, 0.45f, 0.7f}, {0.6f, 0.5f, 0.35f}};
  return palette[p % 6];
}

// The assembly, or its state at one step of the order: the parts before it grey, the step's part in its
// colour with the way it comes home, the parts after it left out.
// Every picture frames the whole assembly, so that the steps line up.
Eigen::AlignedBox3d assembledBounds(const Assembly& a, const SequencePlan& plan, const std::vector<Eigen::Isometry3d>& home) {
  Eigen::AlignedBox3d box;
  for (const PartId p : plan.order)
    for (const auto& v : a.parts[p].mesh->vertices) box.extend(home[p] * v);
  for (const auto& s : plan.stuck)
    for (const auto& v : a.parts[s.part].mesh->vertices) box.extend(home[s.part] * v);
  return box;
}

// `shown`: the positions in the order drawn in colour (the ones before them grey, the ones after left
// out); none: the whole assembly. One part shown gets the arrow of its way home.
std::string picture(const Assembly& a, const SequencePlan& plan, const std::vector<Eigen::Isometry3d>& home, const Eigen::AlignedBox3d& box,
                    std::optional<std::pair<std::size_t, std::size_t>> shown, int w, int h) {
  detail::Picture pic(w, h, box);
  const std::size_t end = shown ? shown->second : plan.order.size();
  for (std::size_t i = 0; i < end && i < plan.order.size(); ++i) {
    const PartId p = plan.order[i];
    const bool current = !shown || i >= shown->first;
    pic.draw({a.parts[p].mesh.get(), home[p], current ? colorOf(a, p) : Eigen::Vector3f(0.78f, 0.78f, 0.78f)});
  }
  if (!shown)
    for (const auto& s : plan.stuck) pic.draw({a.parts[s.part].mesh.get(), home[s.part], Eigen::Vector3f(0.85f, 0.15f, 0.15f)});
  if (shown && shown->first > 0 && shown->second == shown->first + 1)
    if (const Direction* way = plan.wayOf(plan.order[shown->first])) {
      const PartId p = plan.order[shown->first];
      const Eigen::Vector3d centre = home[p] * a.parts[p].mass.centerOfMass;
      pic.arrow(centre + 0.25 * way->out * box.diagonal().norm() * 0.3, -way->out, 0.25 * box.diagonal().norm(),
                Eigen::Vector3f(0.85f, 0.1f, 0.1f));
    }
  return pic.dataUri();
}

// A way home: the parts already in grey, the part at home in its colour, the space its way needs
// translucent (or an arrow along it, without a swept volume), and its nearest pass: a line between the two
// nearest points with a ring on the other part, red for a near miss. Framed on the parts in and the way.
std::string wayPicture(const Assembly& a, const SequencePlan& plan, const std::vector<Eigen::Isometry3d>& home, const eval::WayClearance& w,
                       double threshold, int width, int height) {
  Eigen::AlignedBox3d box;
  const auto upTo = std::find(plan.order.begin(), plan.order.end(), w.part);
  for (auto it = plan.order.begin(); it != plan.order.end() && it <= upTo; ++it)
    for (const auto& v : a.parts[*it].mesh->vertices) box.extend(home[*it] * v);
  for (const auto& v : a.parts[w.part].mesh->vertices) box.extend(home[w.part] * v + w.length * w.out);
  detail::Picture pic(width, height, box);
  for (auto it = plan.order.begin(); it != upTo && it != plan.order.end(); ++it)
    pic.draw({a.parts[*it].mesh.get(), home[*it], Eigen::Vector3f(0.78f, 0.78f, 0.78f)});
  pic.draw({a.parts[w.part].mesh.get(), home[w.part], colorOf(a, w.part)});
  if (w.swept) {
    const TriMesh space = w.swept->surface();
    pic.draw({&space, Eigen::Isometry3d::Identity(), Eigen::Vector3f(0.35f, 0.6f, 0.95f), 0.35f});
  } else {
    const Eigen::Vector3d centre = home[w.part] * a.parts[w.part].mass.centerOfMass;
    pic.arrow(centre + w.length * w.out, -w.out, w.length, Eigen::Vector3f(0.2f, 0.4f, 0.8f));
  }
  if (const eval::WayObject* n = w.nearest()) {
    const Eigen::Vector3f mark = n->least < threshold ? Eigen::Vector3f(0.85f, 0.1f, 0.1f) : Eigen::Vector3f(0.2f, 0.2f, 0.2f);
    pic.segment(n->onPart, n->onOther, mark, 1.0);
    pic.ring(n->onOther, 7.0, mark);
  }
  return pic.dataUri();
}

// A part's kind: its name without the " #2" its repetition added ("bolt-1 #17" is a "bolt-1").
std::string kindOf(const std::string& name) {
  const auto hash = name.rfind(" #");
  if (hash == std::string::npos || hash + 2 >= name.size()) return name;
  return std::all_of(name.begin() + static_cast<std::ptrdiff_t>(hash) + 2, name.end(), [](char c) { return c >= '0' && c <= '9'; })
             ? name.substr(0, hash)
             : name;
}

// "bolt-1 x54, nut-1 x54" in order of first appearance, at most `most` kinds named.
std::string kindsText(const Assembly& a, const std::vector<PartId>& parts, std::size_t most = 8) {
  std::vector<std::pair<std::string, int>> kinds;
  for (const PartId p : parts) {
    const std::string k = kindOf(a.parts[p].name);
    const auto it = std::find_if(kinds.begin(), kinds.end(), [&](const auto& e) { return e.first == k; });
    if (it == kinds.end()) kinds.emplace_back(k, 1);
    else ++it->second;
  }
  std::string out;
  for (std::size_t i = 0; i < kinds.size() && i < most; ++i)
    out += (out.empty() ? "" : ", ") + kinds[i].first + (kinds[i].second > 1 ? " \u00d7" + std::to_string(kinds[i].second) : "");
  if (kinds.size() > most) out += " and " + std::to_string(kinds.size() - most) + " more kinds";
  return out;
}

// The order's steps: runs of positions with the same step number (the parts any order may put in at once).
std::vector<std::pair<std::size_t, std::size_t>> stepRuns(const SequencePlan& plan) {
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  for (std::size_t i = 0; i < plan.order.size(); ++i)
    if (runs.empty() || plan.step[i] != plan.step[runs.back().first]) runs.emplace_back(i, i + 1);
    else runs.back().second = i + 1;
  return runs;
}

std::string barChart(const std::vector<PartRow>& rows, bool withSessions) {
  double top = 0.0;
  for (const auto& r : rows) {
    top = std::max(top, r.estimate.total_s());
    if (r.timeToPlace.n > 0) top = std::max(top, r.timeToPlace.mean + r.timeToPlace.sd);
  }
  top = std::max(top, 1.0);
  const int rowH = 26, left = 150, width = 520;
  const int height = static_cast<int>(rows.size()) * rowH + 50;
  std::string s = "<svg xmlns='http://www.w3.org/2000/svg' width='" + std::to_string(left + width + 60) + "' height='" +
                  std::to_string(height) + "' role='img' aria-label='time per part'>";
  char buf[512];
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& r = rows[i];
    const int y = static_cast<int>(i) * rowH + 10;
    std::snprintf(buf, sizeof buf, "<text x='%d' y='%d' text-anchor='end' font-size='12'>%s</text>", left - 8, y + 15, html(r.name).c_str());
    s += buf;
    const double est = r.estimate.total_s() / top * width;
    std::snprintf(buf, sizeof buf, "<rect x='%d' y='%d' width='%.1f' height='9' fill='#e08a2c'><title>estimate %s s</title></rect>", left,
                  y + (withSessions ? 12 : 5), est, formatNumber(r.estimate.total_s()).c_str());
    s += buf;
    if (withSessions && r.timeToPlace.n > 0) {
      const double m = r.timeToPlace.mean / top * width, sd = r.timeToPlace.sd / top * width;
      std::snprintf(buf, sizeof buf,
                    "<rect x='%d' y='%d' width='%.1f' height='10' fill='#3a76b4'><title>measured %s s</title></rect>"
                    "<line x1='%.1f' x2='%.1f' y1='%d' y2='%d' stroke='#123' stroke-width='1.5'/>",
                    left, y + 1, m, formatNumber(r.timeToPlace.mean).c_str(), left + m - sd, left + m + sd, y + 6, y + 6);
      s += buf;
    }
  }
  const int axisY = static_cast<int>(rows.size()) * rowH + 14;
  for (int k = 0; k <= 4; ++k) {
    const double v = top * k / 4.0;
    std::snprintf(buf, sizeof buf,
                  "<line x1='%.1f' x2='%.1f' y1='6' y2='%d' stroke='#ccc'/><text x='%.1f' y='%d' font-size='11' text-anchor='middle'>%.1f s</text>",
                  left + width * k / 4.0, left + width * k / 4.0, axisY, left + width * k / 4.0, axisY + 14, v);
    s += buf;
  }
  return s + "</svg>";
}

// A chart of a few dozen bars is read; one of a thousand is not: beyond that, a bar per kind of part
// ("bolt-1 (x54)"), the kind's mean estimate and mean time to place.
std::vector<PartRow> chartRows(std::vector<PartRow> rows) {
  constexpr std::size_t kBars = 60;
  if (rows.size() <= kBars) return rows;
  std::vector<PartRow> kinds;
  std::vector<int> count;
  std::vector<std::vector<double>> times;
  for (const PartRow& r : rows) {
    const std::string k = kindOf(r.name);
    std::size_t i = 0;
    while (i < kinds.size() && kinds[i].name != k) ++i;
    if (i == kinds.size()) {
      kinds.push_back(r);
      kinds.back().name = k;
      kinds.back().estimate.handling_s = kinds.back().estimate.insertion_s = 0.0;
      count.push_back(0);
      times.emplace_back();
    }
    kinds[i].estimate.handling_s += r.estimate.handling_s;
    kinds[i].estimate.insertion_s += r.estimate.insertion_s;
    ++count[i];
    if (r.timeToPlace.n > 0) times[i].push_back(r.timeToPlace.mean);
  }
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    kinds[i].estimate.handling_s /= count[i];
    kinds[i].estimate.insertion_s /= count[i];
    if (count[i] > 1) kinds[i].name += " (\u00d7" + std::to_string(count[i]) + ")";
    kinds[i].timeToPlace = spread(times[i]);
  }
  return kinds;
}

const char* stateColor(interact::PartState s) {
  switch (s) {
    case interact::PartState::InHand: return "#3a76b4";
    case interact::PartState::OnTool: return "#7b5ea7";
    case interact::PartState::OnBaseSlide: return "#e08a2c";
    case interact::PartState::OnBaseStatic: return "#f2c14e";
    case interact::PartState::InSpace: return "#d9534f";
    case interact::PartState::Static: return "#c8c8c8";
    case interact::PartState::Placed: return "#4f9d4f";
  }
  return "#000";
}

std::string timeline(const Assembly& a, const SessionStats& s) {
  std::vector<PartId> parts;
  for (const auto& p : s.parts) parts.push_back(p.part);
  const int rowH = 18, left = 150, width = 620;
  const int height = static_cast<int>(parts.size()) * rowH + 60;
  const double T = std::max(s.duration_s, 1e-6);
  std::string out = "<svg xmlns='http://www.w3.org/2000/svg' width='" + std::to_string(left + width + 20) + "' height='" +
                    std::to_string(height) + "' role='img' aria-label='timeline'>";
  char buf[512];
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const int y = static_cast<int>(i) * rowH + 6;
    std::snprintf(buf, sizeof buf, "<text x='%d' y='%d' text-anchor='end' font-size='11'>%s</text>", left - 6, y + 12,
                  html(a.parts[parts[i]].name).c_str());
    out += buf;
    for (const auto& sp : s.spans) {
      if (sp.part != parts[i]) continue;
      std::snprintf(buf, sizeof buf, "<rect x='%.2f' y='%d' width='%.2f' height='%d' fill='%s'><title>%s %.2f-%.2f s</title></rect>",
                    left + sp.from_s / T * width, y, std::max(0.5, (sp.to_s - sp.from_s) / T * width), rowH - 4, stateColor(sp.state),
                    std::string(interact::name(sp.state)).c_str(), sp.from_s, sp.to_s);
      out += buf;
    }
  }
  const int axisY = static_cast<int>(parts.size()) * rowH + 10;
  for (int k = 0; k <= 5; ++k) {
    std::snprintf(buf, sizeof buf, "<text x='%.1f' y='%d' font-size='11' text-anchor='middle'>%.1f s</text>", left + width * k / 5.0,
                  axisY + 12, T * k / 5.0);
    out += buf;
  }
  int x = 20;
  for (const auto st : interact::kAllStates) {
    std::snprintf(buf, sizeof buf, "<rect x='%d' y='%d' width='10' height='10' fill='%s'/><text x='%d' y='%d' font-size='10'>%s</text>", x,
                  axisY + 22, stateColor(st), x + 13, axisY + 31, std::string(interact::name(st)).c_str());
    out += buf;
    x += 104;
  }
  return out + "</svg>";
}

}  // namespace

std::string formatNumber(double v) {
  // to_chars: the CSV's point whatever the locale the window runs in.
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, 3);
  return std::string(buf, r.ptr);
}

std::vector<PartRow> partRows(const Assembly& a, const SequencePlan& plan, const std::vector<SessionStats>& sessions) {
  std::vector<PartRow> rows;
  const Comparison cmp = compare(sessions);
  std::vector<PartId> ids = plan.order;
  for (const auto& s : plan.stuck) ids.push_back(s.part);
  for (const PartId p : ids) {
    PartRow r;
    r.part = p;
    r.name = a.parts[p].name;
    const auto at = std::find(plan.order.begin(), plan.order.end(), p);
    const Direction* way = plan.wayOf(p);
    if (a.base && p == *a.base) {
      r.step = "base";
    } else if (at != plan.order.end()) {
      r.step = std::to_string(plan.step[static_cast<std::size_t>(at - plan.order.begin())]);
      r.comesHome = travelText(way->out) + ": " + way->from;
    } else {
      r.step = "no order";
      for (const auto& s : plan.stuck)
        if (s.part == p) {
          std::set<std::string> names;
          for (const auto& by : s.blockers)
            for (const PartId b : by) names.insert(a.parts[b].name);
          for (const PartId w : s.waitsFor) names.insert(a.parts[w].name + " (partner)");
          for (const auto& n : names) r.blockedBy += (r.blockedBy.empty() ? "" : " ") + n;
        }
    }
    if (!(a.base && p == *a.base)) {
      const PartCheck* c = plan.checkOf(p);
      // A part no order inserts is estimated along its first way home.
      const Direction* d = way ? way : (c && !c->directions.empty() ? &c->directions.front() : nullptr);
      r.estimate = estimateDfa(a, p, d ? d->out : Eigen::Vector3d::UnitZ(), d && d->constraint ? &a.constraints[*d->constraint] : nullptr);
    }
    r.sessions = static_cast<int>(sessions.size());
    for (const auto& pa : cmp.parts)
      if (pa.name == r.name) {
        r.placedIn = pa.placedIn;
        r.timeToPlace = pa.timeToPlace;
        r.grabs = pa.grabs;
        r.drops = pa.drops;
        r.refusals = pa.refusals;
        r.carried = pa.carried;
      }
    bool left = false, right = false, both = false, hoist = false;
    for (const auto& s : sessions)
      if (const PartSession* ps = s.find(p)) {
        left = left || ps->left;
        right = right || ps->right;
        both = both || ps->both;
        hoist = hoist || ps->hoist;
      }
    PartSession all;
    all.left = left;
    all.right = right;
    all.both = both;
    all.hoist = hoist;
    r.hands = all.holders();
    rows.push_back(std::move(r));
  }
  return rows;
}

json waysJson(const Assembly& a, const WaysHome& ways) {
  const auto names = [&](const std::vector<PartId>& parts) {
    std::vector<std::string> out;
    for (const PartId q : parts) out.push_back(a.parts[q].name);
    return out;
  };
  const auto xyz = [](const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); };
  json parts = json::array();
  for (const auto& w : ways.ways) {
    json objects = json::array();
    for (const auto& o : w.objects)
      objects.push_back({{"part", a.parts[o.part].name}, {"least_m", o.least}, {"at_m", o.at}, {"on_part", xyz(o.onPart)}, {"on_other", xyz(o.onOther)}});
    json e{{"part", a.parts[w.part].name}, {"out", xyz(w.out)}, {"length_m", w.length}, {"slides_on", names(w.guides)},
           {"rests_on", names(w.seatedOn)}, {"near_miss", w.nearMiss(ways.options.threshold)}, {"objects", objects}};
    if (w.swept) e["swept"] = {{"volume_m3", w.swept->volume}, {"voxel_m", w.swept->voxel}, {"voxels", w.swept->voxels}};
    parts.push_back(e);
  }
  return {{"threshold_m", ways.options.threshold}, {"reach_m", ways.options.reach}, {"tolerance_m", ways.options.tolerance},
          {"voxel_m", ways.options.voxel}, {"parts", parts}};
}

// What overlaps at rest, for the report: the table (clashes in red), interferences.csv, evaluation.json's rows.
struct OverlapSection {
  std::string html, csv;
  json rows = json::array();
};

OverlapSection overlapSection(const Assembly& a, const std::vector<collision::Interference>& all) {
  using Kind = collision::Interference::Kind;
  OverlapSection s;
  s.csv = "kind,thread,part,with,volume_mm3,depth_mm,x_mm,y_mm,z_mm\n";
  std::size_t count[4] = {0, 0, 0, 0};
  std::string rows;
  for (const auto& i : all) {
    ++count[static_cast<int>(i.kind)];
    const std::string kind(collision::name(i.kind));
    s.rows.push_back({{"kind", kind}, {"thread", i.thread}, {"parts", {a.parts[i.a].name, a.parts[i.b].name}}, {"volume_m3", i.volume},
                      {"depth_m", i.depth}, {"where_m", {i.where.x(), i.where.y(), i.where.z()}}});
    if (i.kind == Kind::Contact) continue;
    s.csv += kind + "," + csv(i.thread) + "," + csv(a.parts[i.a].name) + "," + csv(a.parts[i.b].name) + "," + formatNumber(1e9 * i.volume) + "," +
             formatNumber(1e3 * i.depth) + "," + formatNumber(1e3 * i.where.x()) + "," + formatNumber(1e3 * i.where.y()) + "," +
             formatNumber(1e3 * i.where.z()) + "\n";
    rows += std::string("<tr") + (i.kind == Kind::Clash ? " class='stuck'" : "") + "><td>" +
            html(i.kind == Kind::Threaded ? "threaded " + i.thread : i.kind == Kind::Press ? std::string("press fit") : std::string("clash")) +
            "</td><td>" + html(a.parts[i.a].name) + "</td><td>" + html(a.parts[i.b].name) + "</td><td class='n'>" + formatNumber(1e9 * i.volume) +
            "</td><td class='n'>" + formatNumber(1e3 * i.depth) + "</td></tr>\n";
  }
  s.html = "<h2>Interferences at rest</h2>\n<p>Every pair of parts whose solids share volume where the file places them: " +
           std::to_string(count[static_cast<int>(Kind::Clash)]) + " clash(es), a modelling error to correct (red); " +
           std::to_string(count[static_cast<int>(Kind::Threaded)]) + " thread(s) modelled at the tap drill and " +
           std::to_string(count[static_cast<int>(Kind::Press)]) + " press fit(s), which are fits; " +
           std::to_string(count[static_cast<int>(Kind::Contact)]) + " pair(s) only touch.</p>\n";
  if (!rows.empty())
    s.html += "<table id='interferences'><tr><th>kind</th><th>part</th><th>with</th><th>volume mm&sup3;</th><th>depth mm</th></tr>\n" + rows +
              "</table>\n";
  return s;
}

namespace {

std::string spreadCell(const Spread& s) { return s.n > 0 ? formatNumber(s.mean) : std::string(); }
std::string sdCell(const Spread& s) { return s.n > 1 ? formatNumber(s.sd) : std::string(); }

std::string namesOf(const Assembly& a, const std::vector<PartId>& parts) {
  std::string out;
  for (const PartId q : parts) out += (out.empty() ? "" : " ") + a.parts[q].name;
  return out;
}

// parts.csv: the parts table.
std::string partsCsv(const std::vector<PartRow>& rows) {
  std::string partsCsv =
      "part,step,comes_home,blocked_by,handling_code,insertion_code,handling_s,insertion_s,estimate_s,estimate_is_lower_bound,sessions,"
      "placed_in,time_to_place_mean_s,time_to_place_sd_s,grabs_mean,drops_mean,refusals_mean,carried_mean_m,held_by\n";
  for (const auto& r : rows) {
    const bool base = r.step == "base";
    partsCsv += csv(r.name) + "," + r.step + "," + csv(r.comesHome) + "," + csv(r.blockedBy) + "," + (base ? "" : r.estimate.handlingCode) + "," +
                (base ? "" : r.estimate.insertionCode) + "," + (base ? "" : formatNumber(r.estimate.handling_s)) + "," +
                (base ? "" : formatNumber(r.estimate.insertion_s)) + "," + (base ? "" : formatNumber(r.estimate.total_s())) + "," +
                (base ? "" : r.estimate.lowerBound ? "yes" : "no") + "," + std::to_string(r.sessions) + "," + std::to_string(r.placedIn) + "," +
                spreadCell(r.timeToPlace) + "," + sdCell(r.timeToPlace) + "," + spreadCell(r.grabs) + "," + spreadCell(r.drops) + "," +
                spreadCell(r.refusals) + "," + spreadCell(r.carried) + "," + csv(r.hands) + "\n";
  }
  return partsCsv;
}

// sequence.csv: the order with what each step rests on.
std::string sequenceCsv(const Assembly& a, const SequencePlan& plan) {
  std::string sequenceCsv = "position,step,part,comes_home,after\n";
  for (std::size_t i = 0; i < plan.order.size(); ++i) {
    const PartId p = plan.order[i];
    std::string after;
    for (const auto& e : plan.precedence)
      if (e.after == p)
        after += (after.empty() ? "" : " ") + a.parts[e.before].name + (e.reason == Precedence::Reason::Partner ? "(partner)" : "(blocks)");
    const Direction* way = plan.wayOf(p);
    sequenceCsv += std::to_string(i) + "," + std::to_string(plan.step[i]) + "," + csv(a.parts[p].name) + "," +
                   csv(way ? travelText(way->out) + ": " + way->from : std::string()) + "," + csv(after) + "\n";
  }
  return sequenceCsv;
}

// sessions.csv: every part in every session.
std::string sessionsCsv(const std::vector<SessionStats>& sessions) {
  std::string sessionsCsv = "session,part,first_handled_s,placed_s,time_to_place_s,grabs,tool_lifts,drops,refusals,blocked,carried_m,held_by\n";
  for (const auto& s : sessions)
    for (const auto& p : s.parts)
      sessionsCsv += csv(s.label) + "," + csv(p.name) + "," + (p.firstHandled_s ? formatNumber(*p.firstHandled_s) : "") + "," +
                     (p.placed_s ? formatNumber(*p.placed_s) : "") + "," + (p.timeToPlace() ? formatNumber(*p.timeToPlace()) : "") + "," +
                     std::to_string(p.grabs) + "," + std::to_string(p.toolLifts) + "," + std::to_string(p.drops) + "," +
                     std::to_string(p.refusals.size()) + "," + std::to_string(p.blocked.size()) + "," + formatNumber(p.carried_m) + "," +
                     csv(p.holders()) + "\n";
  return sessionsCsv;
}

// evaluation.json: everything, as numbers (the ways and the interferences are added where they are found).
json evaluationJson(const Assembly& a, const SequencePlan& plan, const std::vector<PartRow>& rows, const std::vector<SessionStats>& sessions) {
  const bool withSessions = !sessions.empty();
  json j;
  j["assembly"] = a.name;
  j["complete"] = plan.complete();
  json jr = json::array();
  for (const auto& r : rows) {
    json e{{"part", r.name}, {"step", r.step}, {"comes_home", r.comesHome}, {"blocked_by", r.blockedBy}};
    if (r.step != "base")
      e["estimate"] = {{"handling_code", r.estimate.handlingCode}, {"insertion_code", r.estimate.insertionCode},
                       {"handling_s", r.estimate.handling_s}, {"insertion_s", r.estimate.insertion_s},
                       {"alpha_deg", r.estimate.alpha_deg}, {"beta_deg", r.estimate.beta_deg}, {"size_m", r.estimate.size_m},
                       {"thickness_m", r.estimate.thickness_m}, {"lower_bound", r.estimate.lowerBound}, {"why", r.estimate.why}};
    if (withSessions)
      e["sessions"] = {{"placed_in", r.placedIn}, {"time_to_place_mean_s", r.timeToPlace.mean}, {"time_to_place_sd_s", r.timeToPlace.sd},
                       {"grabs_mean", r.grabs.mean}, {"drops_mean", r.drops.mean}, {"refusals_mean", r.refusals.mean},
                       {"carried_mean_m", r.carried.mean}, {"held_by", r.hands}};
    jr.push_back(e);
  }
  j["parts"] = jr;
  json js = json::array();
  for (const auto& s : sessions) {
    json parts = json::array();
    for (const auto& p : s.parts) {
      json e{{"part", p.name}, {"grabs", p.grabs}, {"tool_lifts", p.toolLifts}, {"drops", p.drops}, {"refusals", p.refusals},
             {"blocked", p.blocked}, {"carried_m", p.carried_m}, {"held_by", p.holders()}};
      e["first_handled_s"] = p.firstHandled_s ? json(*p.firstHandled_s) : json(nullptr);
      e["placed_s"] = p.placed_s ? json(*p.placed_s) : json(nullptr);
      parts.push_back(e);
    }
    json order = json::array();
    for (const PartId p : s.placedOrder) order.push_back(a.parts[p].name);
    js.push_back({{"session", s.label}, {"duration_s", s.duration_s}, {"placed_order", order}, {"grabs", s.grabs}, {"drops", s.drops},
                  {"refusals", s.refusals}, {"blocked", s.blocked}, {"carried_m", s.carried_m}, {"parts", parts}});
  }
  j["sessions"] = js;
  return j;
}

// ways.csv: each way home's nearest pass, in the order.
std::string waysCsv(const Assembly& a, const SequencePlan& plan, const WaysHome* waysHome) {
  const double threshold = waysHome ? waysHome->options.threshold : 0.0;
  std::string waysCsv =
      "part,comes_home,length_mm,slides_on,rests_on,nearest,least_mm,at_mm,near_miss,swept_cm3,nearest_on_part_mm,nearest_on_other_mm\n";
  if (waysHome) {
    const auto point = [](const Eigen::Vector3d& v) { return formatNumber(1e3 * v.x()) + " " + formatNumber(1e3 * v.y()) + " " + formatNumber(1e3 * v.z()); };
    for (const auto& w : waysHome->ways) {
      const Direction* way = plan.wayOf(w.part);
      const eval::WayObject* n = w.nearest();
      waysCsv += csv(a.parts[w.part].name) + "," + csv(way ? travelText(way->out) + ": " + way->from : std::string()) + "," +
                 formatNumber(1e3 * w.length) + "," + csv(namesOf(a, w.guides)) + "," + csv(namesOf(a, w.seatedOn)) + "," +
                 (n ? csv(a.parts[n->part].name) + "," + formatNumber(1e3 * n->least) + "," + formatNumber(1e3 * n->at) : std::string(",,")) + "," +
                 (w.nearMiss(threshold) ? "yes" : "no") + "," + (w.swept ? formatNumber(1e6 * w.swept->volume) : std::string()) + "," +
                 (n ? point(n->onPart) + "," + point(n->onOther) : std::string(",")) + "\n";
    }
  }
  return waysCsv;
}

// report.html up to its 3D view: the style, the title and what the order comes to.
std::string pageHead(const Assembly& a, const SequencePlan& plan) {
  std::string h = "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'><title>" + html(a.name) +
                  ": assembly evaluation</title><style>"
                  "body{font-family:sans-serif;margin:24px;color:#222;max-width:1100px}"
                  "table{border-collapse:collapse;margin:8px 0 20px}td,th{border:1px solid #ccc;padding:3px 7px;font-size:13px}"
                  "th{background:#eef2f6;text-align:left}td.n{text-align:right}.stuck{color:#b22}tr.miss td{background:#fde9d9}"
                  "tr.sel td{background:#dbe7fb}.steps{display:flex;flex-wrap:wrap;gap:10px}.steps figure{margin:0;width:320px}figcaption{font-size:12px}"
                  "</style></head><body>\n";
  h += "<h1>" + html(a.name) + "</h1>\n<p>" +
       (plan.complete() ? "An order puts every part in place."
                        : std::to_string(plan.stuck.size()) + " part(s) can be put in place by no order (red in the picture).") +
       " " + std::to_string(plan.order.size()) + " parts in the order, base " + html(a.parts[*plan.base].name) + ".</p>\n";
  return h;
}

std::string summaryTable(const Assembly& a, const SequencePlan& plan, const std::vector<PartRow>& rows,
                         const std::vector<std::pair<std::size_t, std::size_t>>& runs) {
  std::string h;
  // The steps first, one row each: what goes in, how, and what it costs by the estimate.
  std::map<PartId, double> estimate;
  for (const auto& r : rows) estimate[r.part] = r.estimate.total_s();
  h += "<h2>Summary</h2>\n<table id='summary'><tr><th>step</th><th>parts</th><th>which</th><th>comes home</th><th>estimate s</th></tr>\n";
  double total = 0.0;
  for (const auto& [from, to] : runs) {
    std::vector<PartId> parts(plan.order.begin() + static_cast<std::ptrdiff_t>(from), plan.order.begin() + static_cast<std::ptrdiff_t>(to));
    std::set<std::string> ways;
    double sum = 0.0;
    for (const PartId p : parts) {
      if (const Direction* way = plan.wayOf(p)) ways.insert(travelText(way->out));
      if (p != *plan.base) sum += estimate[p];
    }
    total += sum;
    std::string how;
    for (const auto& w : ways) how += (how.empty() ? "" : ", ") + w;
    h += "<tr><td class='n'>" + std::to_string(plan.step[from]) + "</td><td class='n'>" + std::to_string(parts.size()) + "</td><td>" +
         html(kindsText(a, parts)) + "</td><td>" + html(from == 0 && parts.size() == 1 ? "(the base)" : how) + "</td><td class='n'>" +
         formatNumber(sum) + "</td></tr>\n";
  }
  h += "<tr><th></th><th class='n'>" + std::to_string(plan.order.size()) + "</th><th>" +
       (plan.stuck.empty() ? std::string() : std::to_string(plan.stuck.size()) + " without an order") + "</th><th></th><th class='n'>" +
       formatNumber(total) + "</th></tr>\n</table>\n";
  return h;
}

// The parts no order puts in, each way home with what blocks it.
std::string stuckTable(const Assembly& a, const SequencePlan& plan) {
  std::string h;
  if (!plan.complete()) {
    h += "<h2 class='stuck'>No order puts these in place</h2>\n<table id='stuck'><tr><th>part</th><th>way home</th><th>blocked by</th></tr>\n";
    for (const auto& s : plan.stuck) {
      const PartCheck* c = plan.checkOf(s.part);
      if (!s.waitsFor.empty() || !c) {
        std::string names;
        for (const PartId w : s.waitsFor) names += (names.empty() ? "" : ", ") + a.parts[w].name;
        h += "<tr><td>" + html(a.parts[s.part].name) + "</td><td>its partner first</td><td>" + html(names) + "</td></tr>\n";
        continue;
      }
      for (std::size_t k = 0; k < c->directions.size(); ++k) {
        std::string names;
        for (const auto& b : c->directions[k].blockers)
          names += (names.empty() ? "" : ", ") + a.parts[b.by].name + " after " + formatNumber(1e3 * b.distance) + " mm";
        h += "<tr><td>" + html(a.parts[s.part].name) + "</td><td>" + html(travelText(c->directions[k].out) + " (" + c->directions[k].from + ")") +
             "</td><td>" + html(names) + "</td></tr>\n";
      }
    }
    h += "</table>\n";
  }
  return h;
}

// The ways pictured: near misses first, then by least clearance, `most` at most.
std::vector<const eval::WayClearance*> picturedWays(const WaysHome* waysHome, std::size_t most) {
  std::vector<const eval::WayClearance*> pictured;
  if (!waysHome) return pictured;
  for (const auto& w : waysHome->ways) pictured.push_back(&w);
  std::stable_sort(pictured.begin(), pictured.end(), [](const eval::WayClearance* x, const eval::WayClearance* y) {
    const double lx = x->objects.empty() ? std::numeric_limits<double>::infinity() : x->objects.front().least;
    const double ly = y->objects.empty() ? std::numeric_limits<double>::infinity() : y->objects.front().least;
    return lx < ly;
  });
  pictured.resize(std::min(pictured.size(), most));
  return pictured;
}

// The order's pictures: the assembly, then each shown part or step in its turn (`drawn` is told each one).
std::string orderPictures(const Assembly& a, const SequencePlan& plan, const std::vector<Eigen::Isometry3d>& home, const Eigen::AlignedBox3d& box,
                          const std::vector<std::pair<std::size_t, std::size_t>>& runs, const std::vector<std::pair<std::size_t, std::size_t>>& shown,
                          bool perStep, const std::function<void(std::size_t)>& drawn) {
  std::string h;
  h += "<img alt='the assembly' width='640' height='440' src='" + picture(a, plan, home, box, std::nullopt, 640, 440) + "'>\n";
  h += "<h2>Order</h2>\n";
  if (perStep)
    h += "<p>" + std::to_string(plan.order.size()) + " parts in " + std::to_string(runs.size()) +
         " steps: a picture per step, its parts in colour; each part's place is in the table below.</p>\n";
  h += "<div class='steps'>\n";
  for (std::size_t k = 0; k < shown.size(); ++k) {
    drawn(k + 1);
    const auto [from, to] = shown[k];
    const PartId p = plan.order[from];
    std::string caption;
    if (perStep) {
      const std::vector<PartId> parts(plan.order.begin() + static_cast<std::ptrdiff_t>(from), plan.order.begin() + static_cast<std::ptrdiff_t>(to));
      caption = "step " + std::to_string(plan.step[from]) + ": " + std::to_string(to - from) + " part" + (to - from == 1 ? "" : "s") + ", <b>" +
                html(kindsText(a, parts, 4)) + "</b>";
    } else {
      const Direction* way = plan.wayOf(p);
      caption = std::to_string(from) + ". step " + std::to_string(plan.step[from]) + ": <b>" + html(a.parts[p].name) + "</b> " +
                (way ? html(travelText(way->out) + " (" + way->from + ")") : std::string("(the base)"));
    }
    h += "<figure><img alt='step " + std::to_string(plan.step[from]) + "' width='320' height='220' src='" +
         picture(a, plan, home, box, shown[k], 320, 220) + "'><figcaption>" + caption + "</figcaption></figure>\n";
  }
  h += "</div>\n";
  if (perStep && runs.size() > shown.size())
    h += "<p>Steps after " + std::to_string(plan.step[shown.back().first]) + " are in the tables only.</p>\n";
  return h;
}

// The ways home: the table of nearest passes and the pictures of the nearest (`drawn` is told each picture).
std::string waysSection(const Assembly& a, const SequencePlan& plan, const std::vector<Eigen::Isometry3d>& home, const WaysHome* waysHome,
                        const std::vector<const eval::WayClearance*>& pictured, const std::function<void(std::size_t)>& drawn) {
  const double threshold = waysHome->options.threshold;
  std::string h;
  std::size_t misses = 0;
  for (const auto& w : waysHome->ways) misses += w.nearMiss(threshold) ? 1 : 0;
  const auto mm = [](double m) { return formatNumber(1e3 * m); };
  // Settings in the prose as people type them: "5 mm", "0.1 mm".
  const auto setting = [](double m) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", 1e3 * m);
    return std::string(b);
  };
  h += "<h2>Ways home: clearance and space</h2>\n<p>Each part's way home in the order, walked from where it is clear of the assembly "
       "to its place, past the parts already in: its least distance to each (found to within " + setting(waysHome->options.tolerance) +
       " mm). A part closer than " + setting(threshold) + " mm to one it neither slides on nor rests on is a near miss, even when its way is free: " +
       std::to_string(misses) + " of " + std::to_string(waysHome->ways.size()) + ". The parts it slides on (its inserts' partners along the way) "
       "are left out; the parts it rests on count until the last " + setting(threshold) + " mm of its approach." +
       (waysHome->options.voxel > 0.0 ? " Blue: the space the way needs, swept at " + setting(waysHome->options.voxel) + " mm voxels." : std::string()) +
       "</p>\n<table id='ways'><tr><th>part</th><th>comes home</th><th>slides on</th><th>rests on</th><th>nearest it passes</th>"
       "<th>least mm</th><th>where: mm out</th><th>swept cm&sup3;</th></tr>\n";
  for (const auto& w : waysHome->ways) {
    const Direction* way = plan.wayOf(w.part);
    const eval::WayObject* n = w.nearest();
    const bool miss = w.nearMiss(threshold);
    h += std::string("<tr") + (miss ? " class='miss'" : "") + "><td>" + html(a.parts[w.part].name) + "</td><td>" +
         html(way ? travelText(way->out) : std::string()) + "</td><td>" + html(namesOf(a, w.guides)) + "</td><td>" + html(namesOf(a, w.seatedOn)) +
         "</td><td>" + (n ? html(a.parts[n->part].name) : std::string("nothing within ") + setting(waysHome->options.reach) + " mm") + "</td><td class='n'>" +
         (n ? mm(n->least) + (miss ? " near miss" : "") : std::string()) + "</td><td class='n'>" + (n ? mm(n->at) : std::string()) +
         "</td><td class='n'>" + (w.swept ? formatNumber(1e6 * w.swept->volume) : std::string()) + "</td></tr>\n";
  }
  h += "</table>\n<div class='steps'>\n";
  for (std::size_t k = 0; k < pictured.size(); ++k) {
    drawn(k);
    const eval::WayClearance& w = *pictured[k];
    const eval::WayObject* n = w.nearest();
    h += "<figure><img alt='way home of " + html(a.parts[w.part].name) + "' width='320' height='220' src='" +
         wayPicture(a, plan, home, w, threshold, 320, 220) + "'><figcaption><b>" + html(a.parts[w.part].name) + "</b> " +
         html(travelText(w.out)) + (n ? ": " + mm(n->least) + " mm from " + html(a.parts[n->part].name) + (w.nearMiss(threshold) ? " (near miss)" : "") : std::string()) +
         "</figcaption></figure>\n";
  }
  h += "</div>\n";
  if (pictured.size() < waysHome->ways.size())
    h += "<p>The " + std::to_string(pictured.size()) + " nearest passes are pictured; every way is in the table and in ways.csv.</p>\n";
  return h;
}

std::string partsTable(const std::vector<PartRow>& rows, bool withSessions) {
  std::string h = "<h2>Parts</h2>\n<p>Estimate: Boothroyd-Dewhurst manual handling and insertion times (the codes' rows are in the docs);"
       " a part slow in the sessions and slow by the estimate is slow by design.</p>\n"
       "<table id='parts'><tr><th>part</th><th>step</th><th>comes home</th><th>blocked by</th><th>handling</th><th>insertion</th>"
       "<th>estimate s</th>";
  if (withSessions)
    h += "<th>placed in</th><th>time to place s (mean)</th><th>sd</th><th>grabs</th><th>drops</th><th>refusals</th><th>carried m</th><th>held by</th>";
  h += "</tr>\n";
  for (const auto& r : rows) {
    const bool base = r.step == "base";
    h += "<tr" + std::string(r.step == "no order" ? " class='stuck'" : "") + "><td>" + html(r.name) + "</td><td>" + r.step + "</td><td>" +
         html(r.comesHome) + "</td><td>" + html(r.blockedBy) + "</td><td>" + (base ? "" : r.estimate.handlingCode) + "</td><td>" +
         (base ? "" : r.estimate.insertionCode) + "</td><td class='n' title='" + html(r.estimate.why) + "'>" +
         (base ? "" : formatNumber(r.estimate.total_s()) + (r.estimate.lowerBound ? " &ge;" : "")) + "</td>";
    if (withSessions)
      h += "<td class='n'>" + (base ? std::string() : std::to_string(r.placedIn) + "/" + std::to_string(r.sessions)) + "</td><td class='n'>" + spreadCell(r.timeToPlace) +
           "</td><td class='n'>" + sdCell(r.timeToPlace) + "</td><td class='n'>" + spreadCell(r.grabs) + "</td><td class='n'>" +
           spreadCell(r.drops) + "</td><td class='n'>" + spreadCell(r.refusals) + "</td><td class='n'>" + spreadCell(r.carried) + "</td><td>" +
           html(r.hands) + "</td>";
    h += "</tr>\n";
  }
  h += "</table>\n";
  return h;
}

std::string timeChart(const SequencePlan& plan, const std::vector<PartRow>& rows, bool withSessions) {
  const std::vector<PartRow> perPart(rows.begin() + (plan.order.empty() ? 0 : 1), rows.end());
  const std::vector<PartRow> bars = chartRows(perPart);
  return "<h2>Time per part</h2>\n<p>" +
       std::string(bars.size() < perPart.size() ? "One bar per kind of part, the mean over its parts. " : "") + "Orange: the estimate" +
       std::string(withSessions ? "; blue: the mean time from first grab to PLACED over the sessions, with one standard deviation." : ".") +
       "</p>\n" + barChart(bars, withSessions) + "\n";
}

// A section per session: its counts, the order it placed in, its timeline and its refusals.
std::string sessionSections(const Assembly& a, const std::vector<SessionStats>& sessions) {
  std::string h;
  for (const auto& s : sessions) {
    h += "<h2>Session " + html(s.label) + "</h2>\n<p>" + formatNumber(s.duration_s) + " s; " + std::to_string(s.placedOrder.size()) +
         " parts placed; " + std::to_string(s.grabs) + " grabs, " + std::to_string(s.drops) + " drops, " + std::to_string(s.refusals) +
         " refusals, " + std::to_string(s.blocked) + " blocked, " + formatNumber(s.carried_m) + " m carried. Placed in the order:";
    for (const PartId p : s.placedOrder) h += " " + html(a.parts[p].name);
    h += ".</p>\n" + timeline(a, s) + "\n";
    std::string refusals;
    for (const auto& p : s.parts)
      for (const auto& r : p.refusals) refusals += "<li>" + html(p.name + ": " + r) + "</li>";
    if (!refusals.empty()) h += "<p>Refusals:</p><ul>" + refusals + "</ul>\n";
  }
  return h;
}

}  // namespace

ReportFiles writeReport(const Assembly& a, const SequencePlan& plan, const std::vector<SessionStats>& sessions,
                        const std::filesystem::path& dir, const ProgressFn& progress, const WaysHome* waysHome,
                        const std::vector<collision::Interference>* overlaps) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw OutputError(dir.string() + ": cannot create the report folder: " + ec.message());
  const std::vector<PartRow> rows = partRows(a, plan, sessions);
  const bool withSessions = !sessions.empty();
  json j = evaluationJson(a, plan, rows, sessions);
  if (waysHome) j["ways"] = waysJson(a, *waysHome);

  const std::vector<Eigen::Isometry3d> home = eval::homePoses(a);
  const Eigen::AlignedBox3d box = assembledBounds(a, plan, home);
  const auto runs = stepRuns(plan);
  std::string h = pageHead(a, plan) + orderView(a, plan) + summaryTable(a, plan, rows, runs);
  // A picture per part up to a few dozen; beyond, one per step (every part it puts in, in colour).
  constexpr std::size_t kPictures = 40;
  const bool perStep = plan.order.size() > kPictures;
  std::vector<std::pair<std::size_t, std::size_t>> shown;
  if (perStep) shown.assign(runs.begin(), runs.begin() + static_cast<std::ptrdiff_t>(std::min(runs.size(), kPictures)));
  else
    for (std::size_t i = 0; i < plan.order.size(); ++i) shown.emplace_back(i, i + 1);
  const std::vector<const eval::WayClearance*> pictured = picturedWays(waysHome, kPictures);
  const std::size_t pictures = shown.size() + 1 + pictured.size();
  // A picture takes a fraction of a second; the caller may stop between two (nothing is written yet).
  const auto drawn = [&](std::size_t count) {
    if (progress && !progress(static_cast<double>(count) / static_cast<double>(pictures),
                              "drawing picture " + std::to_string(count + 1) + " of " + std::to_string(pictures)))
      throw LoadCancelled();
  };
  drawn(0);
  h += orderPictures(a, plan, home, box, runs, shown, perStep, drawn);
  h += stuckTable(a, plan);
  if (waysHome) h += waysSection(a, plan, home, waysHome, pictured, [&](std::size_t k) { drawn(shown.size() + 1 + k); });
  const std::optional<OverlapSection> overlapsShown = overlaps ? std::optional(overlapSection(a, *overlaps)) : std::nullopt;
  if (overlapsShown) {
    h += overlapsShown->html;
    j["interferences"] = overlapsShown->rows;
  }
  h += partsTable(rows, withSessions) + timeChart(plan, rows, withSessions) + sessionSections(a, sessions);
  // Marks the page once every picture has decoded, for whoever checks the page in a browser (its test).
  h += "<script>addEventListener('load',()=>{document.body.dataset.picturesShown="
       "Array.from(document.images).filter(i=>i.complete&&i.naturalWidth>0).length;});</script>\n";
  h += "<p style='font-size:11px;color:#777'>Written by vaw-sim evaluate; the same numbers are in parts.csv, sequence.csv, sessions.csv" +
       std::string(waysHome ? ", ways.csv" : "") + " and evaluation.json beside this page.</p></body></html>\n";

  ReportFiles files{dir / "report.html", dir / "parts.csv", dir / "sequence.csv", dir / "sessions.csv", dir / "evaluation.json", {}, {}};
  AtomicFile fh(files.html), fp(files.partsCsv), fs(files.sequenceCsv), fss(files.sessionsCsv), fj(files.json);
  std::optional<AtomicFile> fw;
  fh << h;
  fp << partsCsv(rows);
  fs << sequenceCsv(a, plan);
  fss << sessionsCsv(sessions);
  fj << j.dump(2) << "\n";
  std::vector<AtomicFile*> all{&fh, &fp, &fs, &fss, &fj};
  if (waysHome) {
    files.waysCsv = dir / "ways.csv";
    fw.emplace(files.waysCsv);
    *fw << waysCsv(a, plan, waysHome);
    all.push_back(&*fw);
  }
  std::optional<AtomicFile> fi;
  if (overlapsShown) {
    files.interferencesCsv = dir / "interferences.csv";
    fi.emplace(files.interferencesCsv);
    *fi << overlapsShown->csv;
    all.push_back(&*fi);
  }
  for (AtomicFile* f : all) f->finish();
  // The page last: whoever waits for report.html finds the rest there.
  for (auto it = all.rbegin(); it != all.rend(); ++it) (*it)->publish();
  return files;
}

}  // namespace vaw::report
