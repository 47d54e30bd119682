#include "metrics/clear_mot.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>

namespace evade::metrics {

double TrueObject::distance_to(Vec2 p) const {
  const double d = radius > 0.0 ? std::hypot(p.x - centre.x, p.y - centre.y) - radius : signed_distance(box, p);
  return std::max(d, 0.0);
}

double MotTotals::mota() const {
  if (objects == 0) return 1.0;
  return 1.0 - static_cast<double>(misses + false_positives + id_switches) / static_cast<double>(objects);
}

std::optional<double> MotTotals::motp_m() const {
  if (matches == 0) return std::nullopt;
  return centre_error_sum_m / static_cast<double>(matches);
}

std::map<int, int64_t> ClearMot::match(const std::vector<TrueObject>& objects, const std::vector<Hypothesis>& hyps) {
  std::map<int, int64_t> out;
  std::set<int64_t> taken;
  std::map<int64_t, const Hypothesis*> by_id;
  for (const Hypothesis& h : hyps) by_id[h.id] = &h;
  for (const TrueObject& o : objects) {  // 1. last frame's match, if still within the gate
    auto hist = history_.find(o.id);
    if (hist == history_.end() || !hist->second.prev_frame_hyp) continue;
    auto h = by_id.find(*hist->second.prev_frame_hyp);
    if (h != by_id.end() && !taken.count(h->first) && o.distance_to(h->second->centre) <= gate_m_) {
      out[o.id] = h->first;
      taken.insert(h->first);
    }
  }
  std::vector<std::tuple<double, int, int64_t>> pairs;  // 2. nearest first
  for (const TrueObject& o : objects) {
    if (out.count(o.id)) continue;
    for (const Hypothesis& h : hyps) {
      if (taken.count(h.id)) continue;
      const double d = o.distance_to(h.centre);
      if (d <= gate_m_) pairs.emplace_back(d, o.id, h.id);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  for (const auto& [d, oid, hid] : pairs) {
    if (out.count(oid) || taken.count(hid)) continue;
    out[oid] = hid;
    taken.insert(hid);
  }
  return out;
}

void ClearMot::count(double t_s, double dt_s, const std::vector<TrueObject>& objects,
                     const std::vector<Hypothesis>& hyps, const std::map<int, int64_t>& matches) {
  std::set<int64_t> matched_hyps;
  for (const auto& [oid, hid] : matches) matched_hyps.insert(hid);
  for (const TrueObject& o : objects) {
    History& h = history_[o.id];
    auto m = matches.find(o.id);
    if (o.scored) {
      ++totals_.objects;
      ++h.scored;
      if (!h.first_scored_s) h.first_scored_s = t_s;
      if (m == matches.end()) {
        ++totals_.misses;
        totals_.merges += std::any_of(hyps.begin(), hyps.end(), [&](const Hypothesis& x) {
          return matched_hyps.count(x.id) && o.distance_to(x.centre) <= gate_m_;
        });
        if (h.was_tracked) h.gap_after_track = true;
      } else {
        const Hypothesis& hyp =
            *std::find_if(hyps.begin(), hyps.end(), [&](const Hypothesis& x) { return x.id == m->second; });
        ++totals_.matches;
        ++h.matched;
        totals_.centre_error_sum_m += std::hypot(hyp.centre.x - o.centre.x, hyp.centre.y - o.centre.y);
        totals_.track_s += dt_s;
        if (h.last_hyp && *h.last_hyp != m->second) ++totals_.id_switches;
        if (h.gap_after_track) ++totals_.fragmentations;
        h.gap_after_track = false;
        h.was_tracked = true;
        if (!h.first_matched_s) h.first_matched_s = t_s;
      }
    }
    if (m != matches.end()) h.last_hyp = m->second;
    h.prev_frame_hyp = m == matches.end() ? std::nullopt : std::optional<int64_t>(m->second);
  }
  for (const Hypothesis& hyp : hyps) {
    if (matched_hyps.count(hyp.id) || !hyp.in_range) continue;
    const bool near_unscored = std::any_of(objects.begin(), objects.end(), [&](const TrueObject& o) {
      return !o.scored && o.distance_to(hyp.centre) <= gate_m_;
    });
    if (near_unscored) continue;
    ++totals_.false_positives;
    const bool on_matched = std::any_of(objects.begin(), objects.end(), [&](const TrueObject& o) {
      return o.scored && matches.count(o.id) && o.distance_to(hyp.centre) <= gate_m_;
    });
    totals_.splits += on_matched;
  }
  ++totals_.frames;
}

std::map<int, int64_t> ClearMot::add_frame(double t_s, double dt_s, const std::vector<TrueObject>& objects,
                                           const std::vector<Hypothesis>& hyps) {
  std::map<int, int64_t> matches = match(objects, hyps);
  count(t_s, dt_s, objects, hyps, matches);
  return matches;
}

MotTotals ClearMot::totals() const {
  MotTotals t = totals_;
  for (const auto& [id, h] : history_) {
    if (h.scored == 0) continue;
    const double ratio = static_cast<double>(h.matched) / static_cast<double>(h.scored);
    if (ratio >= 0.8)
      ++t.mostly_tracked;
    else if (ratio <= 0.2)
      ++t.mostly_lost;
    else
      ++t.partially_tracked;
    if (h.first_matched_s)
      t.time_to_track_s.push_back(*h.first_matched_s - *h.first_scored_s);
    else
      ++t.never_tracked;
  }
  return t;
}

}  // namespace evade::metrics
