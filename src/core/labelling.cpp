#include "core/labelling.hpp"

#include <algorithm>
#include <deque>
#include <map>
#include <unordered_map>

namespace trisnap::detail {
namespace {

class Labeller {
public:
    Labeller(Mesh& mesh, FaceLabels& out) : m_mesh(mesh), m_out(out) {}

    void run()
    {
        auto& tri = m_mesh.tri();
        for (auto f : tri.all_face_handles()) f->info().label = cdt::k_no_id;
        const std::uint32_t outside = intern({});
        std::deque<cdt::Face_handle> queue{tri.infinite_face()};
        tri.infinite_face()->info().label = outside;
        while (!queue.empty()) {
            const cdt::Face_handle f = queue.front();
            queue.pop_front();
            for (int i = 0; i < 3; ++i) visit_neighbour(f, i, queue);
        }
    }

private:
    void visit_neighbour(cdt::Face_handle f, int i, std::deque<cdt::Face_handle>& queue)
    {
        const cdt::Face_handle n = f->neighbor(i);
        if (n->info().label != cdt::k_no_id) return;
        n->info().label = f->is_constrained(i) ? crossed(f->info().label, f, i) : f->info().label;
        queue.push_back(n);
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
        // Nearly every crossing toggles one feature, and the same few transitions repeat along a
        // boundary: remembered by (label, feature), so the interning map (ordered sets of
        // features) is searched once per transition, not once per crossed edge.
        const auto [it, added] = m_steps.try_emplace((std::uint64_t{label} << 32) | m_odd[0], 0u);
        if (added) it->second = toggled(label);
        return it->second;
    }

    // The label of `label`'s set with the features in m_odd toggled.
    std::uint32_t toggled(std::uint32_t label)
    {
        std::vector<std::uint32_t> next;
        const std::vector<std::uint32_t>& cur = m_out.sets[label];
        std::set_symmetric_difference(cur.begin(), cur.end(), m_odd.begin(), m_odd.end(), std::back_inserter(next));
        return intern(std::move(next));
    }

    std::uint32_t intern(std::vector<std::uint32_t> set)
    {
        auto [it, added] = m_index.try_emplace(set, static_cast<std::uint32_t>(m_out.sets.size()));
        if (added) m_out.sets.push_back(std::move(set));
        return it->second;
    }

    Mesh& m_mesh;
    FaceLabels& m_out;
    std::map<std::vector<std::uint32_t>, std::uint32_t> m_index;
    std::vector<OwnerRef> m_refs;
    std::vector<FeatureCount> m_counts;
    std::vector<std::uint32_t> m_odd; ///< features an edge's owners toggle (odd count)
    std::unordered_map<std::uint64_t, std::uint32_t> m_steps; ///< (label, feature) -> label across
};

} // namespace

FaceLabels label_faces(Mesh& mesh, std::size_t feature_count)
{
    FaceLabels out;
    Labeller(mesh, out).run();
    out.faces_of.resize(feature_count);
    for (auto f : mesh.tri().finite_face_handles())
        for (std::uint32_t feature : out.sets[f->info().label]) out.faces_of[feature].push_back(f);
    return out;
}

} // namespace trisnap::detail
