#include "app/shards.hpp"

#include "config/errors.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <functional>
#include <numeric>
#include <queue>

namespace trisnap {
namespace {

/// A non-negative integer from an environment variable or a flag; nullopt when unset or empty.
std::optional<long long> env_number(const EnvLookup& env, const char* name)
{
    const char* text = env(name);
    if (text == nullptr || *text == '\0') {
        return std::nullopt;
    }
    char* end = nullptr;
    errno = 0;
    const long long value = std::strtoll(text, &end, 10);
    if (*end != '\0' || errno != 0 || value < 0) {
        throw argument_error(fmt::format("{}='{}' is not a task index (a whole number >= 0)", name, text));
    }
    return value;
}

/// This task's index and where it came from, or nullopt when nothing gives one.
std::optional<std::pair<long long, std::string>> task_index(std::optional<long long> shard, const EnvLookup& env)
{
    if (shard) {
        return std::make_pair(*shard, std::string("--shard"));
    }
    if (const auto id = env_number(env, "SLURM_ARRAY_TASK_ID")) {
        const long long min = env_number(env, "SLURM_ARRAY_TASK_MIN").value_or(0);
        return std::make_pair(*id - min, std::string("SLURM_ARRAY_TASK_ID"));
    }
    for (const char* name : {"JOB_COMPLETION_INDEX", "AWS_BATCH_JOB_ARRAY_INDEX"}) {
        if (const auto id = env_number(env, name)) {
            return std::make_pair(*id, std::string(name));
        }
    }
    return std::nullopt;
}

std::pair<long long, std::string> task_count(std::optional<long long> count, std::size_t recorded, const EnvLookup& env)
{
    if (count) {
        return {*count, "--num-shards"};
    }
    if (const auto n = env_number(env, "SLURM_ARRAY_TASK_COUNT")) {
        return {*n, "SLURM_ARRAY_TASK_COUNT"};
    }
    if (recorded > 0) {
        return {static_cast<long long>(recorded), "the plan"};
    }
    throw argument_error("no number of shards: give --num-shards N (the array's size)");
}

} // namespace

std::vector<ShardTile> planned_tiles(const stitch::TileLayout& layout)
{
    std::vector<ShardTile> tiles;
    for (std::size_t leaf = 0; leaf < layout.plan.size(); ++leaf) {
        if (layout.bucket_features[leaf] > 0) {
            tiles.push_back(ShardTile{leaf, layout.bucket_vertices[leaf]});
        }
    }
    return tiles;
}

std::vector<std::size_t> assign_shards(const std::vector<ShardTile>& tiles, std::size_t shards)
{
    std::vector<std::size_t> order(tiles.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        if (tiles[a].vertices != tiles[b].vertices) {
            return tiles[a].vertices > tiles[b].vertices;
        }
        return tiles[a].id < tiles[b].id;
    });
    // (load, shard), least load first, then lowest shard.
    using Load = std::pair<std::uint64_t, std::size_t>;
    std::priority_queue<Load, std::vector<Load>, std::greater<>> least;
    for (std::size_t s = 0; s < shards; ++s) {
        least.emplace(0, s);
    }
    std::vector<std::size_t> owner(tiles.size(), 0);
    for (std::size_t k : order) {
        const auto [load, shard] = least.top();
        least.pop();
        owner[k] = shard;
        least.emplace(load + tiles[k].vertices, shard);
    }
    return owner;
}

std::vector<std::uint64_t> shard_loads(const std::vector<ShardTile>& tiles, const std::vector<std::size_t>& owner,
                                       std::size_t shards)
{
    std::vector<std::uint64_t> loads(shards, 0);
    for (std::size_t k = 0; k < tiles.size(); ++k) {
        loads[owner[k]] += tiles[k].vertices;
    }
    return loads;
}

std::size_t suggest_shards(const std::vector<ShardTile>& tiles)
{
    std::uint64_t vertices = 0;
    for (const ShardTile& t : tiles) {
        vertices += t.vertices;
    }
    const std::size_t by_tiles = tiles.size() / k_tiles_per_shard;
    const std::size_t by_vertices = static_cast<std::size_t>(vertices / k_vertices_per_shard);
    return std::clamp<std::size_t>(std::min(by_tiles, by_vertices), 1, k_max_shards);
}

ShardIndex resolve_shard(std::optional<long long> shard, std::optional<long long> count, std::size_t recorded,
                         const EnvLookup& env)
{
    const auto [n, n_source] = task_count(count, recorded, env);
    if (n < 1) {
        throw argument_error(fmt::format("{} {}: the number of shards must be >= 1", n_source, n));
    }
    const auto index = task_index(shard, env);
    if (!index) {
        throw argument_error("no shard index: give --shard I, or run as an array task (SLURM_ARRAY_TASK_ID, "
                             "JOB_COMPLETION_INDEX or AWS_BATCH_JOB_ARRAY_INDEX)");
    }
    const auto& [i, i_source] = *index;
    if (i < 0 || i >= n) {
        const std::string offset = i_source == "SLURM_ARRAY_TASK_ID" ? " (less SLURM_ARRAY_TASK_MIN)" : "";
        throw argument_error(fmt::format("shard {} from {}{} is outside 0..{} ({} shards from {}); give the array "
                                         "as 0-{} (Slurm: --array=0-{})", i, i_source, offset, n - 1, n, n_source,
                                         n - 1, n - 1));
    }
    return ShardIndex{static_cast<std::size_t>(i), static_cast<std::size_t>(n), i_source};
}

std::string list_numbers(const std::vector<std::size_t>& numbers, std::size_t shown)
{
    std::string out;
    for (std::size_t k = 0; k < numbers.size() && k < shown; ++k) {
        out += (k == 0 ? "" : ", ") + std::to_string(numbers[k]);
    }
    if (numbers.size() > shown) {
        out += fmt::format(" and {} more", numbers.size() - shown);
    }
    return out;
}

} // namespace trisnap
