// VAT flocking ("Vásárhelyi with attraction") in the horizontal plane: the
// model of Vásárhelyi et al., "Optimized flocking of autonomous drones in
// confined environments", Science Robotics 3(20), 2018 (repulsion, velocity
// alignment with a braking curve, shill agents for obstacles, speed cutoff),
// with the pairwise attraction of Bonnefond, Simonin and Guérin-Lassous,
// "Extension of flocking models to environments with obstacles and degraded
// communications", IROS 2021, and a migration term towards a target as in the
// DANCERS authors' flocking node. Each term is a pure function of the robot's
// own state, what it heard from its neighbours and the shill agents of the
// obstacles it sees; their sum, capped, is the desired velocity. The formulas,
// the implementations they were checked against (the papers' model sections
// could not be read) and the parameter values: docs/case-study.md.
#ifndef SITLNET_ROBOT_IMAGES_FLOCKER_FLOCKING_H_
#define SITLNET_ROBOT_IMAGES_FLOCKER_FLOCKING_H_

#include <Eigen/Core>
#include <vector>

namespace sitlnet::flocker {

using Vec2 = Eigen::Vector2d;

// Model parameters, named after the papers' symbols, SI units. Defaults: the
// case study's set (docs/case-study.md says where each value comes from).
struct FlockingParams {
  // Self-propulsion along the robot's own velocity and the cutoff
  // (Vásárhelyi et al.), and the constant push towards the target.
  double flock_speed_m_s = 1.5;      // v_flock
  double max_speed_m_s = 1.0;        // v_max
  double migration_speed_m_s = 0.7;  // v_mig
  // Repulsion (Vásárhelyi et al.): a half spring below r0_rep.
  double repulsion_range_m = 5.0;    // r0_rep
  double repulsion_gain_1_s = 0.13;  // p_rep
  // Attraction (Bonnefond et al.): a half spring above r0_att.
  double attraction_range_m = 5.0;    // r0_att
  double attraction_gain_1_s = 0.08;  // p_att
  // Velocity alignment ("friction", Vásárhelyi et al.).
  double friction_range_m = 85.3;     // r0_frict: stopping-point offset
  double friction_coefficient = 0.8;  // C_frict
  double friction_slack_m_s = 0.63;   // v_frict
  double friction_accel_m_s2 = 4.16;  // a_frict
  double friction_gain_1_s = 3.2;     // p_frict
  // Shill agents of obstacles (Vásárhelyi et al.).
  double shill_range_m = 0.3;       // r0_shill
  double shill_speed_m_s = 13.622;  // v_shill
  double shill_accel_m_s2 = 53;     // a_shill
  double shill_gain_1_s = 3.55;     // p_shill
};

// What a robot knows of a neighbour: its last broadcast state.
struct Neighbour {
  Vec2 position_m;
  Vec2 velocity_m_s;
};

// --- The model's terms (each returns a velocity, m/s) ---------------------

// The braking curve D(r, a, p) of Vásárhelyi et al.: the largest velocity
// from which a robot stops within `distance_m` at deceleration `accel_m_s2`,
// linear with slope `gain_1_s` near the stopping point. 0 for r <= 0.
double BrakingSpeed(double distance_m, double accel_m_s2, double gain_1_s);

// v_flock along the robot's own velocity (zero when it stands still).
Vec2 SelfPropulsionTerm(const FlockingParams& params, const Vec2& velocity_m_s);

// v_mig along the unit vector to the target; zero at the target.
Vec2 MigrationTerm(const FlockingParams& params, const Vec2& position_m, const Vec2& target_m);

// Sum over neighbours of p_rep (r0_rep - r_ij) away from j, for r_ij < r0_rep.
Vec2 RepulsionTerm(const FlockingParams& params, const Vec2& position_m,
                   const std::vector<Neighbour>& neighbours);

// Sum over neighbours of p_att (r_ij - r0_att) towards j, for r_ij > r0_att.
Vec2 AttractionTerm(const FlockingParams& params, const Vec2& position_m,
                    const std::vector<Neighbour>& neighbours);

// Sum over neighbours of C_frict (v_ij - v_ij^frictmax) along v_j - v_i where
// the velocity difference v_ij exceeds v_ij^frictmax =
// max(v_frict, D(r_ij - r0_frict, a_frict, p_frict)).
Vec2 AlignmentTerm(const FlockingParams& params, const Vec2& position_m, const Vec2& velocity_m_s,
                   const std::vector<Neighbour>& neighbours);

// One shill agent per obstacle, at the obstacle's point nearest the robot
// (`shill_points_m`, world frame), moving away from it at v_shill; the robot
// aligns to it like to a neighbour with C = 1 and v_is^shillmax =
// D(r_is - r0_shill, a_shill, p_shill).
Vec2 ShillTerm(const FlockingParams& params, const Vec2& position_m, const Vec2& velocity_m_s,
               const std::vector<Vec2>& shill_points_m);

// The desired velocity: the sum of the terms above, its norm capped at v_max.
Vec2 DesiredVelocity(const FlockingParams& params, const Vec2& position_m, const Vec2& velocity_m_s,
                     const std::vector<Neighbour>& neighbours,
                     const std::vector<Vec2>& shill_points_m, const Vec2& target_m);

}  // namespace sitlnet::flocker

#endif  // SITLNET_ROBOT_IMAGES_FLOCKER_FLOCKING_H_
