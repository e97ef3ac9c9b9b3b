#pragma once
// Vertex enumeration of a polytope of at most 5 dimensions given by half-spaces (private to the
// stability analysis, st/validate/stability.h): the extreme free motions of a guide are its vertices.

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace st::stability_detail {

/// {z in R^m : h_j . z >= r_j} (m <= 5) inside the box |z_k| <= B, by cutting the box with one
/// half-space at a time (double description). Two vertices are adjacent when the constraints tight at
/// both have rank m - 1. Where the polytope is simple (m constraints tight at a vertex, as on scanned
/// bone), the edges are read from an index of the vertices by m - 1 of their tight constraints, so a
/// cut costs what it changes; elsewhere (a degenerate vertex, as on CAD-like or synthetic shapes) the
/// candidates sharing m - 1 constraints are counted. Both decide by the same rank test.
class Polytope {
public:
  using Vec5 = Eigen::Matrix<double, 5, 1>;

  Polytope(Eigen::Index m, double box);

  /// Cuts by h . z >= r (h unit, m coordinates). Returns false when nothing is left.
  bool cut(const Eigen::VectorXd& h_m, double r);

  /// The vertices (m coordinates), in the order they were made (the same for any hashing).
  [[nodiscard]] std::vector<Eigen::VectorXd> vertices() const;

private:
  /// A vertex's combinatorics; its position and tolerance are in z_ and eps_ (flat, for the cuts' scan).
  struct Vertex {
    std::vector<int> tight; // sorted ids of the constraints tight at it (its buffer is recycled)
    std::uint64_t made = 0; // creation order
    bool alive = false;
    bool indexed = false; // its m edges are in edges_ (simple vertex)
  };
  struct Fresh { // a vertex made by a cut, before it is placed
    Vec5 z = Vec5::Zero();
    std::vector<int> tight;
  };
  using Key = std::array<int, 4>; // m - 1 sorted constraint ids, unused places -1
  struct KeyHash {
    std::size_t operator()(const Key& k) const noexcept;
  };
  using Ends = std::array<std::int32_t, 2>; // the slots of the (at most two) simple vertices at an edge
  /// Edge key -> ends, open addressing with linear probing (no allocation per edge). Each entry keeps
  /// its key's hash: probes compare it first, and erasing shifts entries without hashing them again.
  class EdgeTable {
  public:
    [[nodiscard]] Ends* find(const Key& key);
    Ends& insert(const Key& key); // the entry, made {-1, -1} when new
    void erase(const Key& key);
    void clear();

  private:
    struct Entry {
      Key key{-1, -1, -1, -1}; // key[0] < 0: free (a key's first id is never negative)
      Ends ends{-1, -1};
      std::uint64_t hash = 0;
    };
    static bool same(const Key& a, const Key& b) {
      return a[0] == b[0] && a[1] == b[1] && a[2] == b[2] && a[3] == b[3];
    }
    Ends& insert(const Key& key, std::uint64_t hash);
    void grow();
    std::vector<Entry> table_;
    std::size_t size_ = 0;
  };

  enum class Side : std::uint8_t { out, on, in };

  /// Closer to a hyperplane than this, a vertex lies on it: no facet thinner than this is made, so no
  /// cluster of vertices a rounding apart (which the rank test would take for adjacent) forms.
  [[nodiscard]] static double tolerance(const Vec5& z) { return 1e-7 * (1.0 + z.norm()); }
  /// Whether the rows `common` have rank m - 1.
  [[nodiscard]] bool adjacent(const std::vector<int>& common) const;
  [[nodiscard]] Key key_without(const Vertex& v, std::size_t skip) const;

  void index(std::int32_t slot);
  void unindex(std::int32_t slot);
  std::int32_t place(Fresh& v); // takes v's tight buffer, leaves it one to reuse
  void remove(std::int32_t slot);
  /// Adds the new vertices, those that coincide within the tolerance as one (their tight sets joined).
  void add_merged();
  /// The inside vertices adjacent to the outside vertex q, by its edges (q indexed) or by counting.
  void neighbours(std::int32_t q, std::vector<std::int32_t>& out);

  Eigen::Index m_;
  std::vector<Vec5> rows_;
  std::vector<Vertex> vertices_; // slots; dead ones are reused
  std::vector<Vec5> z_;          // per slot: position
  std::vector<double> eps_;      // per slot: tolerance(z), negative when the slot is dead
  std::vector<std::int32_t> free_;
  std::vector<std::int32_t> unindexed_; // live vertices not in edges_ (may hold dead slots until a cut)
  EdgeTable edges_;
  std::uint64_t made_ = 0;
  // Per cut:
  std::vector<double> s_;
  std::vector<Side> side_;
  std::vector<std::int32_t> inside_;
  bool counted_ = false;                       // at_ built for this cut
  std::vector<std::vector<std::uint32_t>> at_; // constraint -> positions in inside_ tight at it
  std::vector<int> shared_;
  std::vector<int> common_;
  std::vector<Fresh> fresh_; // the first fresh_count_ are this cut's new vertices
  std::size_t fresh_count_ = 0;
};

} // namespace st::stability_detail
