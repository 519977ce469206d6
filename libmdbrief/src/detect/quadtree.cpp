#include "detect/quadtree.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <queue>
#include <tuple>

namespace mdbrief::detail {

namespace {

struct Cell {
  double x0, y0, x1, y1;        // half-open [x0, x1) x [y0, y1)
  std::vector<int> members;     // indices into the candidates
  int id;                       // creation order: breaks ties between equally full cells

  // A cell narrower than a pixel in both directions holds at most one integer position.
  bool splittable() const { return members.size() > 1 && (x1 - x0 > 1.0 || y1 - y0 > 1.0); }
};

// Most members first, then the older cell, so the split order is deterministic.
struct FewerMembers {
  bool operator()(const Cell* a, const Cell* b) const {
    if (a->members.size() != b->members.size()) return a->members.size() < b->members.size();
    return a->id > b->id;
  }
};

}  // namespace

std::vector<Candidate> spreadWithQuadtree(const std::vector<Candidate>& candidates, int budget,
                                          const cv::Rect& area) {
  if (budget <= 0 || candidates.empty()) return {};
  // Every cell ever made is kept (split ones emptied); a deque keeps the queue's pointers
  // valid while cells are appended.
  std::deque<Cell> cells;
  const int roots = std::max(1, static_cast<int>(std::lround(
                                    static_cast<double>(area.width) / std::max(1, area.height))));
  const double rootWidth = static_cast<double>(area.width) / roots;
  for (int i = 0; i < roots; ++i) {
    cells.push_back({area.x + i * rootWidth, static_cast<double>(area.y),
                     area.x + (i + 1) * rootWidth, static_cast<double>(area.y + area.height),
                     {}, static_cast<int>(cells.size())});
  }
  for (int i = 0; i < static_cast<int>(candidates.size()); ++i) {
    const int root = std::clamp(static_cast<int>((candidates[i].x - area.x) / rootWidth), 0, roots - 1);
    cells[root].members.push_back(i);
  }

  std::priority_queue<Cell*, std::vector<Cell*>, FewerMembers> queue;
  int nonEmpty = 0;
  for (Cell& cell : cells) {
    if (cell.members.empty()) continue;
    ++nonEmpty;
    queue.push(&cell);
  }
  while (nonEmpty < budget && !queue.empty() && queue.top()->splittable()) {
    Cell* parent = queue.top();
    queue.pop();
    const double mx = 0.5 * (parent->x0 + parent->x1), my = 0.5 * (parent->y0 + parent->y1);
    const size_t first = cells.size();
    cells.push_back({parent->x0, parent->y0, mx, my, {}, static_cast<int>(cells.size())});
    cells.push_back({mx, parent->y0, parent->x1, my, {}, static_cast<int>(cells.size())});
    cells.push_back({parent->x0, my, mx, parent->y1, {}, static_cast<int>(cells.size())});
    cells.push_back({mx, my, parent->x1, parent->y1, {}, static_cast<int>(cells.size())});
    for (int index : parent->members) {
      const Candidate& c = candidates[index];
      const size_t quadrant = (c.x >= mx ? 1 : 0) + (c.y >= my ? 2 : 0);
      cells[first + quadrant].members.push_back(index);
    }
    parent->members.clear();
    --nonEmpty;
    for (size_t i = first; i < cells.size(); ++i) {
      if (cells[i].members.empty()) continue;
      ++nonEmpty;
      queue.push(&cells[i]);
    }
  }

  std::vector<Candidate> best;
  best.reserve(nonEmpty);
  for (const Cell& cell : cells) {
    if (cell.members.empty()) continue;
    const int winner = *std::min_element(cell.members.begin(), cell.members.end(),
                                         [&](int a, int b) { return strongerThan(candidates[a], candidates[b]); });
    best.push_back(candidates[winner]);
  }
  std::sort(best.begin(), best.end(), strongerThan);
  if (static_cast<int>(best.size()) > budget) best.resize(budget);
  return best;
}

}  // namespace mdbrief::detail
