// Private: resting under gravity, sleeping, sliding and waking (resting.cpp says how).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "world/world_impl.h"

namespace rattle::detail {

void putToSleep(WorldState& w, uint32_t body, const std::vector<uint32_t>& supporters);
/// The predictive mode's guard against a Zeno sequence: counts a collision of `body` in this step.
void sleepIfZeno(WorldState& w, uint32_t body, double now);
/// Wakes the body and everything resting on it (through `dependents`), appending them to `woken`.
void wakeUp(WorldState& w, uint32_t body, double now, std::vector<uint32_t>& woken);
/// wakeUp in two halves, for a call that must make room before it changes anything: the first finds
/// whom to wake (appending to `woken`, passing over those it already holds) and changes nothing; the
/// second wakes woken[from, end) and does not allocate between steps.
void collectWake(const WorldState& w, uint32_t body, std::vector<uint32_t>& woken);
void applyWake(WorldState& w, const std::vector<uint32_t>& woken, size_t from, double now);
void startSliding(WorldState& w, uint32_t body, uint32_t fixture, int feature, Vec2 normal);
void stopSliding(WorldState& w, detail::BodySlot& b);
bool isFlatFeature(const WorldState& w, uint32_t fixture, int feature);
bool leavesCorner(const WorldState& w, const detail::BodySlot& b, uint32_t fixture, int feature, double now);
int featureLeftByPoint(const WorldState& w, const detail::BodySlot& b, uint32_t fixture, double now);
bool supportsAt(const WorldState& w, uint32_t body, double now, std::vector<uint32_t>& supporters);
std::optional<double> slideEndTime(const WorldState& w, const detail::BodySlot& b, double now, double dt);

}  // namespace rattle::detail
