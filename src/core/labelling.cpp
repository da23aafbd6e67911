#include "core/labelling.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <unordered_map>

namespace trisnap::detail {
namespace {

class Labeller {
public:
    Labeller(Mesh& mesh, FaceLabels& out) : m_mesh(mesh), m_out(out) {}

    void run(std::size_t feature_count)
    {
        auto& tri = m_mesh.tri();
        for (auto f : tri.all_face_handles()) f->info().mark = cdt::k_no_label;
        m_single.assign(feature_count, cdt::k_no_label);
        const std::uint32_t outside = intern({}); // 0: label_faces relies on it
        // Breadth first, one wave after another: the order a FIFO queue gives, in two vectors
        // that keep their room (a deque allocated a block per 64 faces).
        std::vector<cdt::Face_handle> wave{tri.infinite_face()}, next;
        tri.infinite_face()->info().mark = outside;
        while (!wave.empty()) {
            for (const cdt::Face_handle f : wave) {
                for (int i = 0; i < 3; ++i) visit_neighbour(f, i, next);
            }
            wave.swap(next);
            next.clear();
        }
    }

private:
    void visit_neighbour(cdt::Face_handle f, int i, std::vector<cdt::Face_handle>& next)
    {
        const cdt::Face_handle n = f->neighbor(i);
        if (n->info().mark != cdt::k_no_label) return;
        n->info().mark = f->is_constrained(i) ? crossed(f->info().mark, f, i) : f->info().mark;
        next.push_back(n);
    }

    // The label on the other side of constrained edge (f, i).
    std::uint32_t crossed(std::uint32_t label, cdt::Face_handle f, int i)
    {
        auto& tri = m_mesh.tri();
        m_refs.clear();
        m_mesh.owner_refs(f->vertex(tri.cw(i))->info().id, f->vertex(tri.ccw(i))->info().id, m_refs);
        m_mesh.polygon_ownership(m_refs, m_counts);
        m_odd.clear();
        for (const FeatureCount& c : m_counts) {
            if (c.times % 2 == 1) m_odd.push_back(c.feature);
        }
        if (m_odd.empty()) return label;
        if (m_odd.size() > 1) return toggled(label);
        // Nearly every crossing toggles one feature, from outside every polygon into it or out
        // of it again: answered without a lookup. Other transitions repeat along a boundary:
        // remembered by (label, feature), so the interning map (ordered sets of features) is
        // searched once per transition, not once per crossed edge.
        const std::span<const std::uint32_t> cur = m_out.set(label);
        if (cur.empty()) return single(m_odd[0]);
        if (cur.size() == 1 && cur[0] == m_odd[0]) return 0;
        const auto [it, added] = m_steps.try_emplace((std::uint64_t{label} << 32) | m_odd[0], 0u);
        if (added) it->second = toggled(label);
        return it->second;
    }

    // The label of `label`'s set with the features in m_odd toggled.
    std::uint32_t toggled(std::uint32_t label)
    {
        std::vector<std::uint32_t> next;
        const std::span<const std::uint32_t> cur = m_out.set(label);
        std::set_symmetric_difference(cur.begin(), cur.end(), m_odd.begin(), m_odd.end(), std::back_inserter(next));
        if (next.size() == 1) return single(next[0]);
        return intern(std::move(next));
    }

    // The label of {feature}: kept per feature, not in the map (nearly every label is one).
    std::uint32_t single(std::uint32_t feature)
    {
        std::uint32_t& l = m_single[feature];
        if (l == cdt::k_no_label) l = add_label(std::span(&feature, 1));
        return l;
    }

    // The label of a set of 0 or >= 2 features (single() has those of one).
    std::uint32_t intern(std::vector<std::uint32_t> set)
    {
        const auto it = m_index.find(set);
        if (it != m_index.end()) return it->second;
        const std::uint32_t l = add_label(set);
        m_index.emplace(std::move(set), l);
        return l;
    }

    // Labels are numbered in the order their sets are first met.
    std::uint32_t add_label(std::span<const std::uint32_t> set)
    {
        if (m_out.labels() >= cdt::k_no_label) {
            throw std::length_error("more than 2^28 - 1 distinct sets of overlapping features: split the layer in tiles");
        }
        m_out.set_features.insert(m_out.set_features.end(), set.begin(), set.end());
        m_out.set_first.push_back(m_out.set_features.size());
        return static_cast<std::uint32_t>(m_out.labels() - 1);
    }

    Mesh& m_mesh;
    FaceLabels& m_out;
    std::map<std::vector<std::uint32_t>, std::uint32_t> m_index;
    std::vector<std::uint32_t> m_single; ///< feature -> the label of {feature}, k_no_label: none yet
    std::vector<OwnerRef> m_refs;
    std::vector<FeatureCount> m_counts;
    std::vector<std::uint32_t> m_odd; ///< features an edge's owners toggle (odd count)
    std::unordered_map<std::uint64_t, std::uint32_t> m_steps; ///< (label, feature) -> label across
};

} // namespace

FaceLabels label_faces(Mesh& mesh, std::size_t feature_count)
{
    FaceLabels out;
    Labeller(mesh, out).run(feature_count);
    // Counted, then placed: the same faces in the same order per feature as pushing them.
    std::vector<std::size_t>& first = out.first;
    first.assign(feature_count + 1, 0);
    for (auto f : mesh.tri().finite_face_handles())
        for (std::uint32_t feature : out.set(f->info().mark)) ++first[feature + 1];
    for (std::size_t k = 0; k < feature_count; ++k) first[k + 1] += first[k];
    const std::size_t blocks = (feature_count + FaceLabels::k_block - 1) / FaceLabels::k_block;
    out.blocks.resize(blocks);
    for (std::size_t b = 0; b < blocks; ++b) {
        const std::size_t lo = b * FaceLabels::k_block, hi = std::min(feature_count, lo + FaceLabels::k_block);
        out.blocks[b].resize(first[hi] - first[lo]);
    }
    // The labels were kept in the faces' marks, which the searches use as stamps from here on:
    // each finite face's mark goes back to 0 once placed. The infinite faces hold the outside
    // label, which is 0 (interned first; they meet only across unconstrained edges).
    std::vector<std::size_t> next(first.begin(), first.end() - 1); // where feature f's next face goes
    for (auto f : mesh.tri().finite_face_handles()) {
        for (std::uint32_t feature : out.set(f->info().mark)) {
            const std::size_t b = feature / FaceLabels::k_block;
            out.blocks[b][next[feature]++ - first[b * FaceLabels::k_block]] = f;
        }
        f->info().mark = 0;
    }
    return out;
}

} // namespace trisnap::detail
