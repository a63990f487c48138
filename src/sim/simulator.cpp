#include "barn/sim/simulator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <box2d/box2d.h>

#include "barn/core/config.hpp"
#include "barn/core/text_io.hpp"

namespace barn::sim {

namespace {

// Collision filtering: the robot's fixtures make no Box2D contacts (see the header).
constexpr uint16 kObstacleCategory = 0x0001;
constexpr uint16 kRobotCategory = 0x0002;

double clampAbs(double value, double limit) { return std::clamp(value, -limit, limit); }

}  // namespace

void validate(const PhysicsConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);  // every rule is a field's range
}

bool rectOverlapsCircle(const core::Pose2& pose, const core::Rect& rect, const Eigen::Vector2d& centre, double radius) {
  return rect.squaredDistance(pose.inverseTransform(centre)) < radius * radius;  // circle centre in the robot frame
}

struct Simulator::Box2D {
  b2World world{b2Vec2(0.0f, 0.0f)};
  b2Body* robot = nullptr;
};

std::uint64_t plantHash(const core::RobotConfig& robot, const PhysicsConfig& physics) {
  const std::uint64_t robot_hash = core::fnv1a64("robot:\n" + core::writeConfig(robot));
  const std::uint64_t hash = core::fnv1a64("physics:\n" + core::writeConfig(physics), robot_hash);
  return hash == 0 ? 1 : hash;  // 0 means unknown
}

Simulator::Simulator(const ObstacleField& field, const core::RobotConfig& robot, const PhysicsConfig& physics,
                     const core::Pose2& start, std::uint64_t seed)
    : field_(&field), robot_(robot), physics_(physics), rects_(robot.collisionRects()),
      box2d_(std::make_unique<Box2D>()), pose_(start), slip_noise_(seed) {
  b2World& world = box2d_->world;
  world.SetAllowSleeping(false);

  // All cylinders on one static body.
  b2BodyDef ground_def;
  b2Body* ground = world.CreateBody(&ground_def);
  b2CircleShape circle;
  b2FixtureDef cylinder_def;
  cylinder_def.shape = &circle;
  cylinder_def.filter.categoryBits = kObstacleCategory;
  for (std::size_t i = 0; i < field.centres.size(); ++i) {
    const Eigen::Vector2d& c = field.centres[i];
    circle.m_radius = static_cast<float>(field.radiusOf(i));
    circle.m_p.Set(static_cast<float>(c.x()), static_cast<float>(c.y()));
    cylinder_def.userData.pointer = i;  // index of the exact (double) centre
    ground->CreateFixture(&cylinder_def);
  }

  // The robot: chassis and wheels as polygons with mass, no contacts (exact test instead).
  b2BodyDef robot_def;
  robot_def.type = b2_dynamicBody;
  robot_def.position.Set(static_cast<float>(start.x), static_cast<float>(start.y));
  robot_def.angle = static_cast<float>(start.yaw);
  box2d_->robot = world.CreateBody(&robot_def);
  double area = 0.0;
  for (const core::Rect& r : rects_) area += 4.0 * r.halfLength() * r.halfWidth();
  for (const core::Rect& r : rects_) {
    b2PolygonShape box;
    box.SetAsBox(static_cast<float>(r.halfLength()), static_cast<float>(r.halfWidth()),
                 b2Vec2(static_cast<float>(r.centreX()), static_cast<float>(r.centreY())), 0.0f);
    b2FixtureDef def;
    def.shape = &box;
    def.density = static_cast<float>(robot.mass / area);
    def.filter.categoryBits = kRobotCategory;
    def.filter.maskBits = 0;
    box2d_->robot->CreateFixture(&def);
  }
  collision_ = findCollision(pose_);
}

Simulator::~Simulator() = default;

void Simulator::command(const core::Twist& cmd) {
  cmd_ = cmd;
  cmd_time_ = time_;
}

double Simulator::forwardSpeed() const {
  return std::cos(pose_.yaw) * velocity_.x() + std::sin(pose_.yaw) * velocity_.y();
}

double Simulator::sidewaysSpeed() const {
  return -std::sin(pose_.yaw) * velocity_.x() + std::cos(pose_.yaw) * velocity_.y();
}

void Simulator::step() {
  const double dt = physics_.dt();

  // 1-2. Command timeout and diff_drive_controller limits.
  core::Twist target;
  if (time_ - cmd_time_ <= robot_.cmd_timeout + 1e-9) {
    target.linear = clampAbs(cmd_.linear, robot_.max_linear_speed);
    target.angular = clampAbs(cmd_.angular, robot_.max_angular_speed);
  }
  wheel_.linear += clampAbs(target.linear - wheel_.linear, robot_.max_linear_accel * dt);
  wheel_.angular += clampAbs(target.angular - wheel_.angular, robot_.max_angular_accel * dt);

  // 3. Traction: one friction circle for the change of the body's linear velocity.
  const Eigen::Vector2d heading(std::cos(pose_.yaw), std::sin(pose_.yaw));
  if (robot_.turn_slip_speed > 0.0) {
    // Gauss-Markov slip: decays over turn_slip_time, driven in proportion to the yaw rate.
    const double decay = std::exp(-dt / robot_.turn_slip_time);
    const double sigma = robot_.turn_slip_speed * std::abs(yaw_rate_) * std::sqrt(1.0 - decay * decay);
    slip_ = decay * slip_ + sigma * Eigen::Vector2d(slip_noise_.normal(), slip_noise_.normal());
  }
  // A pivot ahead of the centre makes the centre slide sideways (to the right when turning left).
  const Eigen::Vector2d left(-heading.y(), heading.x());
  const Eigen::Vector2d pivot_slide = -robot_.icr_offset * yaw_rate_ * left;
  Eigen::Vector2d change = wheel_.linear * heading + pivot_slide + slip_ - velocity_;
  const double max_change = robot_.traction_coefficient * robot_.gravity * dt;
  if (change.norm() > max_change) change *= max_change / change.norm();
  velocity_ += change;
  yaw_rate_ += clampAbs(robot_.turn_efficiency * wheel_.angular - yaw_rate_, robot_.max_angular_traction_accel * dt);

  // 4. Integrate with Box2D, then the exact collision test.
  b2Body* body = box2d_->robot;
  body->SetLinearVelocity(b2Vec2(static_cast<float>(velocity_.x()), static_cast<float>(velocity_.y())));
  body->SetAngularVelocity(static_cast<float>(yaw_rate_));
  box2d_->world.Step(static_cast<float>(dt), physics_.velocity_iterations, physics_.position_iterations);
  time_ += dt;
  const b2Vec2 position = body->GetPosition();
  pose_ = {position.x, position.y, core::wrapAngle(body->GetAngle())};
  if (!collision_) {
    collision_ = findCollision(pose_);
    if (collision_) collision_->time = time_;
  }
}

std::optional<CollisionInfo> Simulator::findCollision(const core::Pose2& pose) const {
  // Broad phase: Box2D's tree returns the cylinders whose boxes meet the robot's bounding box.
  struct Query : b2QueryCallback {
    std::vector<b2Fixture*> found;
    bool ReportFixture(b2Fixture* fixture) override {
      if (fixture->GetFilterData().categoryBits == kObstacleCategory) found.push_back(fixture);
      return true;
    }
  } query;
  const float reach = static_cast<float>(robot_.collisionRadius());
  b2AABB box;
  box.lowerBound.Set(static_cast<float>(pose.x) - reach, static_cast<float>(pose.y) - reach);
  box.upperBound.Set(static_cast<float>(pose.x) + reach, static_cast<float>(pose.y) + reach);
  box2d_->world.QueryAABB(&query, box);

  // Narrow phase in double precision against the exact cylinder centres.
  std::optional<CollisionInfo> best;
  for (b2Fixture* fixture : query.found) {
    const std::size_t index = fixture->GetUserData().pointer;
    const Eigen::Vector2d& centre = field_->centres[index];
    const double radius = field_->radiusOf(index);
    for (std::size_t i = 0; i < rects_.size(); ++i) {
      if (rectOverlapsCircle(pose, rects_[i], centre, radius)) {
        if (!best) best = CollisionInfo{time_, centre, static_cast<int>(i), pose};
      }
    }
  }
  return best;
}

bool Simulator::overlaps(const core::Pose2& pose) const { return findCollision(pose).has_value(); }

Simulator::ReferenceScan Simulator::referenceScan(const core::LidarConfig& lidar, const core::Pose2& sensor_pose) const {
  struct ClosestHit : b2RayCastCallback {
    float fraction = 1.0f;
    int hit = -1;
    float ReportFixture(b2Fixture* fixture, const b2Vec2&, const b2Vec2&, float f) override {
      if (fixture->GetFilterData().categoryBits != kObstacleCategory) return -1.0f;  // ignore the robot
      hit = static_cast<int>(fixture->GetUserData().pointer);
      fraction = f;
      return f;  // clip the ray: later reports can only be closer
    }
  };
  ReferenceScan scan;
  scan.ranges.assign(static_cast<std::size_t>(lidar.beams), std::numeric_limits<double>::infinity());
  scan.hit.assign(static_cast<std::size_t>(lidar.beams), -1);
  const double increment = lidar.angleIncrement();
  const b2Vec2 origin(static_cast<float>(sensor_pose.x), static_cast<float>(sensor_pose.y));
  for (int i = 0; i < lidar.beams; ++i) {
    const double angle = sensor_pose.yaw + lidar.angle_min + i * increment;
    const b2Vec2 end(static_cast<float>(sensor_pose.x + lidar.range_max * std::cos(angle)),
                     static_cast<float>(sensor_pose.y + lidar.range_max * std::sin(angle)));
    ClosestHit callback;
    box2d_->world.RayCast(&callback, origin, end);
    if (callback.hit >= 0) {
      const double range = static_cast<double>(callback.fraction) * lidar.range_max;
      scan.ranges[static_cast<std::size_t>(i)] = std::max(range, lidar.range_min);
      scan.hit[static_cast<std::size_t>(i)] = callback.hit;
    }
  }
  return scan;
}

void prepareForThreads() {
  // Make two circles touch once on this thread so b2Contact's registry is initialised.
  b2World world(b2Vec2(0.0f, 0.0f));
  b2BodyDef def;
  b2Body* a = world.CreateBody(&def);
  def.type = b2_dynamicBody;
  b2Body* b = world.CreateBody(&def);
  b2CircleShape circle;
  circle.m_radius = 1.0f;
  a->CreateFixture(&circle, 1.0f);
  b->CreateFixture(&circle, 1.0f);
  world.Step(0.01f, 1, 1);
}

}  // namespace barn::sim
