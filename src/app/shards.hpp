#pragma once
// Shares of a cluster run: which tiles each array task (shard) snaps, which task this process
// is, and how many tasks to suggest. The contract with a scheduler is only an index per task:
// Slurm job arrays, Kubernetes Indexed Jobs and AWS Batch array jobs all give one.
//  - assign_shards: tiles sorted by input vertices (descending, ties by id), each given to the
//    shard with the fewest vertices so far (ties: the lowest shard). Deterministic: every task
//    computes the same assignment from the plan; balanced: no shard holds more than the least
//    loaded one plus the largest tile.
//  - resolve_shard: I from --shard, else SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN,
//    JOB_COMPLETION_INDEX or AWS_BATCH_JOB_ARRAY_INDEX; N from --num-shards, else
//    SLURM_ARRAY_TASK_COUNT, else the number `trisnap plan` recorded. Throws argument_error.
#include "stitch/layout.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace trisnap {

/// A tile as planned: its id (the plan leaf, which is also its group) and its input vertices.
struct ShardTile {
    std::size_t id = 0;
    std::uint64_t vertices = 0;
};

/// The tiles that run, as the plan made them (before any seam merge), in id order.
std::vector<ShardTile> planned_tiles(const stitch::TileLayout& layout);

/// The shard of each tile (same order as `tiles`), for `shards` > 0.
std::vector<std::size_t> assign_shards(const std::vector<ShardTile>& tiles, std::size_t shards);

/// Input vertices per shard under an assignment.
std::vector<std::uint64_t> shard_loads(const std::vector<ShardTile>& tiles, const std::vector<std::size_t>& owner,
                                       std::size_t shards);

/// A number of array tasks for these tiles: each task gets at least k_tiles_per_shard tiles (so
/// the assignment balances) and k_vertices_per_shard vertices (so a task outlasts its start-up),
/// and at most k_max_shards tasks in all (Slurm's default MaxArraySize is 1001).
std::size_t suggest_shards(const std::vector<ShardTile>& tiles);
inline constexpr std::size_t k_tiles_per_shard = 16;
inline constexpr std::uint64_t k_vertices_per_shard = 5'000'000;
inline constexpr std::size_t k_max_shards = 1000;

struct ShardIndex {
    std::size_t index = 0;
    std::size_t count = 1;
    std::string source; ///< where the index came from ("--shard", "SLURM_ARRAY_TASK_ID", ...)
};

/// Environment lookup (std::getenv in the tool; a map in tests).
using EnvLookup = std::function<const char*(const char*)>;

/// This task's shard; `recorded` is the plan's number of shards (0: none).
ShardIndex resolve_shard(std::optional<long long> shard, std::optional<long long> count, std::size_t recorded,
                         const EnvLookup& env);

/// "3, 7, 12 and 40 more": at most `shown` numbers of a list.
std::string list_numbers(const std::vector<std::size_t>& numbers, std::size_t shown = 20);

} // namespace trisnap
