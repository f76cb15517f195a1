#pragma once
/// Step merging: a pass over a found plan that removes the steps a leg can do without. A leg
/// that steps A -> B and later B -> C may often stand on A until it steps A -> C: the search
/// moves a leg when the crawl timing or its workspace box says so, and the next steps of the
/// other legs then leave room it did not know of. Every state the removal changes is checked as
/// the search checks a step (see MergeSteps), so the shorter plan is as valid as the longer one.

#include <optional>
#include <vector>

#include "planner_context.h"
#include "rbcp/core/contact_plan.h"

namespace rbcp::contact_planner_detail {

/// `states` with every step removed that can be. For each step k (leg L, A -> B) whose leg steps
/// again later (index m, B -> C), in order from the first, L either stands on A in states
/// k+1 .. m-1 and steps A -> C at m, or steps A -> C at k and stands on C until m; the first that
/// keeps the plan valid removes a step, and passes repeat until none does. Each changed state
/// keeps its base pose when that stays valid, else its swing's body shift is searched again from
/// there with the new feet (SwingShift). Checked for each changed state: the touch-down stance
/// (the changed foot and the new foothold inside the workspace box scaled by
/// config.merge.workspace_scale, every foot within the kinematic margins, the new foothold's leg
/// clear of the terrain, the feet apart, the swing triangle, robustness, four- and three-foot
/// torques) and its lift-off from the state before (reach, terrain and self collision, swing
/// triangle, three-foot torques, the body's transit); then the lift-off of the step after the
/// changed ones. The first state and each leg's last foothold never change. `removed` (optional)
/// receives the number of steps removed.
std::vector<WholeBodyState> MergeSteps(const PlannerContext& ctx, std::vector<WholeBodyState> states,
                                       int* removed = nullptr);

/// `states` walked from `start` instead of states[0]: start has states[0]'s base pose and
/// footholds but for one foot (one that touched down a few cm beside its foothold). That foot
/// stands where start has it until its leg steps again; each state this changes is checked and
/// made valid as MergeSteps does (its base pose kept when valid, else its swing's body shift
/// searched again), and the leg's next step must lift off from the last of them. The first
/// state's joints are solved again. nullopt when a state is not valid so, when start differs in
/// more than one foot or in its base pose, or when the leg never steps again (its last foothold
/// never changes).
std::optional<std::vector<WholeBodyState>> FromStart(const PlannerContext& ctx,
                                                     const std::vector<WholeBodyState>& states,
                                                     const WholeBodyState& start);

/// `states` on the context's terrain (a map that changed since they were planned): every
/// foothold within `max_offset_m` of a contact surface (where it is: the plan stays the plan), and
/// every state valid there with its own base pose, at touch-down and at lift-off of its step, as
/// step merging checks a state (its joints solved again). nullopt when a foothold has no surface
/// that near or a state is not valid.
std::optional<std::vector<WholeBodyState>> OnTerrain(const PlannerContext& ctx, const std::vector<WholeBodyState>& states,
                                                     double max_offset_m);

}  // namespace rbcp::contact_planner_detail
