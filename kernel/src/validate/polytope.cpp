#include "validate/polytope.h"

#include <algorithm>
#include <iterator>

namespace st::stability_detail {

Polytope::Polytope(Eigen::Index m, double box) : m_(m) {
  for (Eigen::Index k = 0; k < m; ++k) {
    rows_.push_back(Vec5::Unit(k));  // z_k >= -B
    rows_.push_back(-Vec5::Unit(k)); // z_k <= B
  }
  const std::size_t corners = std::size_t{1} << m;
  for (std::size_t bits = 0; bits < corners; ++bits) {
    Fresh v;
    for (Eigen::Index k = 0; k < m; ++k) {
      const bool high = (bits >> k) & 1U;
      v.z(k) = high ? box : -box;
      v.tight.push_back(static_cast<int>(2 * k + (high ? 1 : 0)));
    }
    place(v);
  }
}

std::size_t Polytope::KeyHash::operator()(const Key& k) const noexcept {
  // Independent products, summed, then mixed (the ids are small integers).
  std::uint64_t h = static_cast<std::uint32_t>(k[0]) * 0x9e3779b97f4a7c15ULL +
                    static_cast<std::uint32_t>(k[1]) * 0xbf58476d1ce4e5b9ULL +
                    static_cast<std::uint32_t>(k[2]) * 0x94d049bb133111ebULL +
                    static_cast<std::uint32_t>(k[3]) * 0xd6e8feb86659fd93ULL;
  h ^= h >> 31;
  h *= 0xbf58476d1ce4e5b9ULL;
  return static_cast<std::size_t>(h ^ (h >> 29));
}

Polytope::Ends* Polytope::EdgeTable::find(const Key& key) {
  if (table_.empty()) return nullptr;
  const std::uint64_t hash = KeyHash{}(key);
  const std::size_t mask = table_.size() - 1;
  for (std::size_t i = hash & mask;; i = (i + 1) & mask) {
    Entry& e = table_[i];
    if (e.key[0] < 0) return nullptr;
    if (e.hash == hash && same(e.key, key)) return &e.ends;
  }
}

Polytope::Ends& Polytope::EdgeTable::insert(const Key& key) { return insert(key, KeyHash{}(key)); }

Polytope::Ends& Polytope::EdgeTable::insert(const Key& key, std::uint64_t hash) {
  if (2 * (size_ + 1) > table_.size()) grow();
  const std::size_t mask = table_.size() - 1;
  std::size_t i = hash & mask;
  for (; table_[i].key[0] >= 0; i = (i + 1) & mask)
    if (table_[i].hash == hash && same(table_[i].key, key)) return table_[i].ends;
  table_[i].key = key;
  table_[i].hash = hash;
  table_[i].ends = {-1, -1};
  ++size_;
  return table_[i].ends;
}

void Polytope::EdgeTable::erase(const Key& key) {
  if (table_.empty()) return;
  const std::uint64_t hash = KeyHash{}(key);
  const std::size_t mask = table_.size() - 1;
  std::size_t i = hash & mask;
  for (; !(table_[i].hash == hash && same(table_[i].key, key)); i = (i + 1) & mask)
    if (table_[i].key[0] < 0) return;
  // Backward shift: move up each later entry of the run whose home does not lie after the hole.
  for (std::size_t j = i;;) {
    table_[i] = Entry{};
    for (;;) {
      j = (j + 1) & mask;
      if (table_[j].key[0] < 0) {
        --size_;
        return;
      }
      const std::size_t k = table_[j].hash & mask;
      const bool stays = i <= j ? (i < k && k <= j) : (i < k || k <= j);
      if (!stays) break;
    }
    table_[i] = table_[j];
    i = j;
  }
}

void Polytope::EdgeTable::clear() {
  table_.clear();
  size_ = 0;
}

void Polytope::EdgeTable::grow() {
  std::vector<Entry> old = std::move(table_);
  table_.assign(std::max<std::size_t>(1024, 2 * old.size()), Entry{});
  size_ = 0;
  for (const Entry& e : old)
    if (e.key[0] >= 0) insert(e.key, e.hash) = e.ends;
}

Polytope::Key Polytope::key_without(const Vertex& v, std::size_t skip) const {
  Key k{-1, -1, -1, -1};
  std::size_t n = 0;
  for (std::size_t i = 0; i < v.tight.size(); ++i)
    if (i != skip) k[n++] = v.tight[i];
  return k;
}

void Polytope::index(std::int32_t slot) {
  Vertex& v = vertices_[static_cast<std::size_t>(slot)];
  if (m_ < 2 || v.tight.size() != static_cast<std::size_t>(m_)) return;
  for (std::size_t skip = 0; skip < v.tight.size(); ++skip) { // an edge with two simple ends already: leave it
    const Ends* e = edges_.find(key_without(v, skip));
    if (e && (*e)[0] >= 0 && (*e)[1] >= 0) return;
  }
  for (std::size_t skip = 0; skip < v.tight.size(); ++skip) {
    Ends& e = edges_.insert(key_without(v, skip));
    e[e[0] < 0 ? 0 : 1] = slot;
  }
  v.indexed = true;
}

void Polytope::unindex(std::int32_t slot) {
  Vertex& v = vertices_[static_cast<std::size_t>(slot)];
  if (!v.indexed) return;
  for (std::size_t skip = 0; skip < v.tight.size(); ++skip) {
    const Key key = key_without(v, skip);
    Ends* e = edges_.find(key);
    if (!e) continue;
    for (std::int32_t& end : *e)
      if (end == slot) end = -1;
    if ((*e)[0] < 0 && (*e)[1] < 0) edges_.erase(key);
  }
  v.indexed = false;
}

std::int32_t Polytope::place(Fresh& v) {
  std::int32_t slot;
  if (!free_.empty()) {
    slot = free_.back();
    free_.pop_back();
  } else {
    slot = static_cast<std::int32_t>(vertices_.size());
    vertices_.emplace_back();
    z_.emplace_back();
    eps_.push_back(-1.0);
  }
  const auto i = static_cast<std::size_t>(slot);
  Vertex& dst = vertices_[i];
  dst.tight.swap(v.tight);
  v.tight.clear();
  dst.alive = true;
  dst.indexed = false;
  dst.made = made_++;
  z_[i] = v.z;
  eps_[i] = tolerance(v.z);
  index(slot);
  if (!dst.indexed) unindexed_.push_back(slot);
  return slot;
}

void Polytope::remove(std::int32_t slot) {
  unindex(slot);
  Vertex& v = vertices_[static_cast<std::size_t>(slot)];
  v.alive = false;
  v.tight.clear();
  eps_[static_cast<std::size_t>(slot)] = -1.0;
  free_.push_back(slot);
}

void Polytope::neighbours(std::int32_t q, std::vector<std::int32_t>& out) {
  out.clear();
  const Vertex& vq = vertices_[static_cast<std::size_t>(q)];
  const auto inside = [&](std::int32_t p) {
    return p >= 0 && side_[static_cast<std::size_t>(p)] == Side::in && vertices_[static_cast<std::size_t>(p)].alive;
  };
  if (vq.indexed) {
    for (std::size_t skip = 0; skip < vq.tight.size(); ++skip) {
      const Ends* e = edges_.find(key_without(vq, skip));
      if (!e) continue;
      for (const std::int32_t p : *e)
        if (p != q && inside(p)) out.push_back(p);
    }
    // Degenerate vertices are not in the index: those sharing m - 1 constraints with q are candidates.
    for (const std::int32_t p : unindexed_) {
      if (!inside(p)) continue;
      const std::vector<int>& tp = vertices_[static_cast<std::size_t>(p)].tight;
      std::size_t shared = 0;
      for (const int c : vq.tight) shared += std::binary_search(tp.begin(), tp.end(), c) ? 1U : 0U;
      if (shared + 1 >= vq.tight.size()) out.push_back(p);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return;
  }
  // Count, through an index from each constraint to the inside vertices tight at it, the constraints
  // each inside vertex shares with q; candidates share at least m - 1.
  if (!counted_) {
    if (at_.size() < rows_.size()) at_.resize(rows_.size());
    for (std::uint32_t k = 0; k < inside_.size(); ++k)
      for (const int c : vertices_[static_cast<std::size_t>(inside_[k])].tight)
        at_[static_cast<std::size_t>(c)].push_back(k);
    shared_.assign(inside_.size(), 0);
    counted_ = true;
  }
  if (m_ <= 1) { // a segment: its two ends are adjacent, nothing need be shared
    out = inside_;
    return;
  }
  std::vector<std::uint32_t> touched;
  for (const int c : vq.tight)
    for (const std::uint32_t k : at_[static_cast<std::size_t>(c)])
      if (shared_[k]++ == 0) touched.push_back(k);
  for (const std::uint32_t k : touched) {
    if (shared_[k] >= m_ - 1) out.push_back(inside_[k]);
    shared_[k] = 0;
  }
}

bool Polytope::cut(const Eigen::VectorXd& h_m, double r) {
  Vec5 h = Vec5::Zero();
  h.head(m_) = h_m;
  const std::size_t n = z_.size();
  s_.resize(n);
  side_.resize(n);
  bool any_out = false, any_in = false;
  for (std::size_t i = 0; i < n; ++i) {
    const double s = h.dot(z_[i]) - r, eps = eps_[i];
    s_[i] = s;
    if (eps < 0.0) { // a dead slot
      side_[i] = Side::on;
      continue;
    }
    side_[i] = s < -eps ? Side::out : s <= eps ? Side::on : Side::in;
    any_out |= side_[i] == Side::out;
    any_in |= side_[i] != Side::out;
  }
  if (!any_out) return true; // redundant: it never cuts later either (the polytope only shrinks)
  if (!any_in) {
    vertices_.clear();
    z_.clear();
    eps_.clear();
    free_.clear();
    unindexed_.clear();
    edges_.clear();
    return false;
  }
  rows_.push_back(h);
  const int id = static_cast<int>(rows_.size()) - 1;
  std::vector<std::int32_t> outside;
  inside_.clear();
  for (std::size_t i = 0; i < vertices_.size(); ++i) {
    if (!vertices_[i].alive) continue;
    const auto slot = static_cast<std::int32_t>(i);
    if (side_[i] == Side::out) outside.push_back(slot);
    else if (side_[i] == Side::in) inside_.push_back(slot);
    else { // on the new hyperplane: kept, no edge to cut; tight at one more, so no longer simple
      unindex(slot);
      vertices_[i].tight.push_back(id);
      unindexed_.push_back(slot);
    }
  }
  counted_ = false;
  fresh_count_ = 0;
  std::vector<std::int32_t> candidates;
  for (const std::int32_t q : outside) {
    neighbours(q, candidates);
    const Vertex& vq = vertices_[static_cast<std::size_t>(q)];
    for (const std::int32_t p : candidates) {
      const Vertex& vp = vertices_[static_cast<std::size_t>(p)];
      common_.clear();
      std::set_intersection(vp.tight.begin(), vp.tight.end(), vq.tight.begin(), vq.tight.end(),
                            std::back_inserter(common_));
      if (!adjacent(common_)) continue;
      const double sp = s_[static_cast<std::size_t>(p)], sq = s_[static_cast<std::size_t>(q)];
      const double t = sp / (sp - sq);
      if (fresh_count_ == fresh_.size()) fresh_.emplace_back();
      Fresh& v = fresh_[fresh_count_++];
      const Vec5& zp = z_[static_cast<std::size_t>(p)];
      v.z = zp + t * (z_[static_cast<std::size_t>(q)] - zp);
      v.tight.assign(common_.begin(), common_.end());
      v.tight.push_back(id);
    }
  }
  if (counted_)
    for (const std::int32_t p : inside_)
      for (const int c : vertices_[static_cast<std::size_t>(p)].tight) at_[static_cast<std::size_t>(c)].clear();
  for (const std::int32_t q : outside) remove(q);
  std::erase_if(unindexed_, [&](std::int32_t p) {
    const Vertex& v = vertices_[static_cast<std::size_t>(p)];
    return !v.alive || v.indexed;
  });
  std::sort(unindexed_.begin(), unindexed_.end());
  unindexed_.erase(std::unique(unindexed_.begin(), unindexed_.end()), unindexed_.end());
  add_merged();
  return true;
}

void Polytope::add_merged() {
  std::vector<std::size_t> order(fresh_count_);
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return fresh_[a].z(0) < fresh_[b].z(0) || (fresh_[a].z(0) == fresh_[b].z(0) && a < b);
  });
  std::vector<char> gone(order.size(), 0);
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (gone[i]) continue;
    Fresh& a = fresh_[order[i]];
    const double tol = tolerance(a.z);
    bool joined = false;
    for (std::size_t j = i + 1; j < order.size() && fresh_[order[j]].z(0) - a.z(0) <= tol; ++j) {
      const Fresh& b = fresh_[order[j]];
      if (!gone[j] && (b.z - a.z).norm() <= tol) {
        gone[j] = 1;
        joined = true;
        a.tight.insert(a.tight.end(), b.tight.begin(), b.tight.end());
      }
    }
    if (joined) {
      std::sort(a.tight.begin(), a.tight.end());
      a.tight.erase(std::unique(a.tight.begin(), a.tight.end()), a.tight.end());
    }
    place(a);
  }
}

bool Polytope::adjacent(const std::vector<int>& common) const {
  if (m_ <= 1) return true;
  std::array<Vec5, 5> basis;
  Eigen::Index rank = 0;
  for (const int c : common) {
    Vec5 r = rows_[static_cast<std::size_t>(c)];
    for (int pass = 0; pass < 2; ++pass)
      for (Eigen::Index k = 0; k < rank; ++k)
        r -= r.dot(basis[static_cast<std::size_t>(k)]) * basis[static_cast<std::size_t>(k)];
    if (r.norm() <= 1e-9) continue;
    if (rank == m_ - 1) return false; // rank m: a single point, not an edge
    basis[static_cast<std::size_t>(rank++)] = r.normalized();
  }
  return rank == m_ - 1;
}

std::vector<Eigen::VectorXd> Polytope::vertices() const {
  std::vector<std::size_t> live;
  for (std::size_t i = 0; i < vertices_.size(); ++i)
    if (vertices_[i].alive) live.push_back(i);
  std::sort(live.begin(), live.end(),
            [&](std::size_t a, std::size_t b) { return vertices_[a].made < vertices_[b].made; });
  std::vector<Eigen::VectorXd> out;
  out.reserve(live.size());
  for (const std::size_t i : live) out.emplace_back(z_[i].head(m_));
  return out;
}

} // namespace st::stability_detail
