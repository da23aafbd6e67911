#include "app/exit_status.hpp"

#include "app/interrupt.hpp"
#include "config/errors.hpp"
#include "stitch/tiled_snap.hpp"

#include <new>

namespace trisnap {
namespace {

constexpr const char* k_memory_hint = "out of memory; give --memory-limit (out of core under that much), or a smaller --bbox";

/// The text of `e` and of every exception nested inside it, outermost first.
std::string full_message(const std::exception& e)
{
    std::string text = e.what();
    try {
        std::rethrow_if_nested(e);
    } catch (const std::exception& inner) {
        text += ": " + full_message(inner);
    } catch (...) {
        text += ": unknown error";
    }
    return text;
}

// "work directory DIR: no room left for the work files (features.bin...: cannot write: No space
// left on device); ...": the directory first, the file relative to it.
std::string disk_full_message(const tiling::disk_full_error& e)
{
    std::string detail = e.what();
    const std::string prefix = e.directory() + "/";
    if (detail.rfind(prefix, 0) == 0) {
        detail.erase(0, prefix.size());
    }
    return "work directory " + e.directory() + ": no room left for the work files (" + detail +
           "); free some space there or give --work-dir on a larger disk";
}

} // namespace

bool is_out_of_memory(const std::exception& e)
{
    if (dynamic_cast<const std::bad_alloc*>(&e) != nullptr) {
        return true;
    }
    try {
        std::rethrow_if_nested(e);
    } catch (const std::exception& inner) {
        return is_out_of_memory(inner);
    } catch (...) {
        return false;
    }
    return false;
}

ExitStatus exit_status(const std::exception& e)
{
    if (dynamic_cast<const std::bad_alloc*>(&e) != nullptr) {
        return {1, k_memory_hint};
    }
    if (is_out_of_memory(e)) {
        return {1, std::string(k_memory_hint) + " (" + e.what() + ")"};
    }
    if (const auto* stop = dynamic_cast<const interrupted*>(&e)) {
        return {stop->signal() == SIGINT ? 130 : 1, e.what()};
    }
    if (const auto* full = dynamic_cast<const tiling::disk_full_error*>(&e)) {
        return {1, disk_full_message(*full)};
    }
    if (dynamic_cast<const stitch::tile_error*>(&e) != nullptr) {
        return {1, std::string(e.what()) + "; nothing was left at OUT (--on-error skip retries the tile merged with "
                                            "its neighbours, then untiled in its region, then reports its features "
                                            "as problem 303 and goes on)"};
    }
    const bool usage = dynamic_cast<const argument_error*>(&e) != nullptr ||
                       dynamic_cast<const config_error*>(&e) != nullptr;
    return {usage ? 2 : 1, full_message(e)};
}

} // namespace trisnap
