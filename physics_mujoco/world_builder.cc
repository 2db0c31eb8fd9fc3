#include "physics_mujoco/world_builder.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace sitlnet::physics {
namespace {

// Shortest text that reads back as the same double.
std::string Num(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::string Triple(double x, double y, double z) { return Num(x) + " " + Num(y) + " " + Num(z); }

// `obstacles`: indices into the scenario's obstacles, in scenario order; null: all of them.
void AppendHeader(const Scenario& scenario, Integrator integrator, int robots,
                  const std::vector<int>* obstacles, std::string* xml) {
  const double timestep_s = static_cast<double>(scenario.physics_step_ns) / kNsPerS;
  // Contacts: a quad touches the ground and a few boxes at once; sizes are explicit because
  // MuJoCo 2.2.2's defaults overflow with many bodies, and mjData holds njmax x njmax matrices
  // (njmax 20480 for 128 robots did not fit in memory): keep the shared model's small.
  const int nconmax = robots == 1 ? 40 : 10 * robots;
  const int njmax = robots == 1 ? 160 : 20 * robots;
  *xml += "<mujoco model=\"sitlnet\">\n";
  *xml += "  <compiler angle=\"degree\" inertiafromgeom=\"false\"/>\n";
  *xml += "  <option timestep=\"" + Num(timestep_s) + "\" gravity=\"0 0 -9.81\" integrator=\"" +
          (integrator == Integrator::kRk4 ? "RK4" : "Euler") + "\"/>\n";
  *xml += "  <size nconmax=\"" + std::to_string(nconmax) + "\" njmax=\"" + std::to_string(njmax) +
          "\"/>\n";
  *xml += "  <worldbody>\n";
  // Ground: an infinite plane at z = 0 (size 0 0: infinite).
  *xml += "    <geom name=\"ground\" type=\"plane\" size=\"0 0 1\"/>\n";
  const auto& boxes = scenario.spec.obstacle();
  const int count = obstacles ? static_cast<int>(obstacles->size()) : boxes.size();
  for (int k = 0; k < count; ++k) {
    const int i = obstacles ? (*obstacles)[k] : k;
    const proto::Obstacle& box = boxes[i];
    *xml += "    <geom name=\"obstacle" + std::to_string(i) + "\" type=\"box\" pos=\"" +
            Triple(box.center_m().x(), box.center_m().y(), box.center_m().z()) + "\" size=\"" +
            Triple(box.size_m().x() / 2, box.size_m().y() / 2, box.size_m().z() / 2) +
            "\" euler=\"0 0 " + Num(box.yaw_deg()) + "\"/>\n";
  }
}

// One multirotor body. Mass and inertia are explicit (inertiafromgeom false): the collision
// box carries no mass, so the body is exactly the airframe's figures, centred on the origin.
// Contacts: time constant 4 ms (penetration scales with speed x time constant; MuJoCo raises it
// to 2 steps for long steps) and damping ratio 4 (a multirotor hitting a wall hardly bounces).
// Into a wall at 2 m/s, measured: MuJoCo's default 0.02 s / 1 gives 16 mm and an 8 % rebound,
// this 11 mm and 1.7 %.
void AppendQuad(const proto::Airframe& airframe, const std::string& suffix, const std::string& pos,
                const std::string& euler, std::string* xml) {
  const auto half = BodyHalfSize(airframe);
  *xml += "    <body name=\"" + std::string(kQuadBodyName) + suffix + "\" pos=\"" + pos +
          "\" euler=\"" + euler + "\">\n";
  *xml += "      <freejoint/>\n";
  *xml += "      <inertial pos=\"0 0 0\" mass=\"" + Num(airframe.mass_kg()) + "\" diaginertia=\"" +
          Triple(airframe.ixx_kg_m2(), airframe.iyy_kg_m2(), airframe.izz_kg_m2()) + "\"/>\n";
  *xml += "      <geom type=\"box\" size=\"" + Triple(half[0], half[1], half[2]) +
          "\" solref=\"0.004 4\"/>\n";
  *xml += "      <site name=\"" + std::string(kImuSiteName) + suffix + "\" pos=\"0 0 0\"/>\n";
  *xml += "    </body>\n";
}

}  // namespace

std::array<double, 3> BodyHalfSize(const proto::Airframe& airframe) {
  if (airframe.has_body_half_size_m()) {
    const auto& size = airframe.body_half_size_m();
    return {size.x(), size.y(), size.z()};
  }
  return {airframe.arm_x_m(), airframe.arm_y_m(),
          0.25 * std::min(airframe.arm_x_m(), airframe.arm_y_m())};
}

std::string SingleRobotWorldXml(const Scenario& scenario, const proto::Airframe& airframe,
                                Integrator integrator, const std::vector<int>* obstacles) {
  std::string xml;
  AppendHeader(scenario, integrator, 1, obstacles, &xml);
  AppendQuad(airframe, "", "0 0 0", "0 0 0", &xml);
  xml += "  </worldbody>\n";
  // The accelerometer gives the specific force including contact forces (IMU at rest on the
  // ground reads +g), computed by MuJoCo from the step's accelerations.
  xml += "  <sensor><accelerometer site=\"" + std::string(kImuSiteName) + "\"/></sensor>\n";
  xml += "</mujoco>\n";
  return xml;
}

std::string AllRobotsWorldXml(const Scenario& scenario, Integrator integrator) {
  std::string xml;
  const int robots = static_cast<int>(scenario.robots.size());
  AppendHeader(scenario, integrator, robots, nullptr, &xml);
  for (const RobotPlan& robot : scenario.robots) {
    const auto& p = robot.spec.position_m();
    AppendQuad(robot.airframe, std::to_string(robot.index), Triple(p.x(), p.y(), p.z()),
               "0 0 " + Num(robot.spec.yaw_deg()), &xml);
  }
  xml += "  </worldbody>\n  <sensor>\n";
  for (const RobotPlan& robot : scenario.robots) {
    xml += "    <accelerometer site=\"" + std::string(kImuSiteName) + std::to_string(robot.index) +
           "\"/>\n";
  }
  xml += "  </sensor>\n</mujoco>\n";
  return xml;
}

}  // namespace sitlnet::physics
