#include "engine/vehicle/driver_inputs.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "engine/input_error.h"
#include "engine/number_format.h"
#include "engine/numeric_csv.h"

namespace pwsim::vehicle {

double Channel::At(double time) const {
  if (t.empty()) return 0.0;
  if (time <= t.front()) return value.front();
  if (time >= t.back()) return value.back();
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(t.begin(), t.end(), time) - t.begin());
  if (hold) return value[i - 1];
  const double w = (time - t[i - 1]) / (t[i] - t[i - 1]);
  return value[i - 1] + w * (value[i] - value[i - 1]);
}

DriverInput InputTables::At(double time) const {
  DriverInput in;
  in.throttle = throttle.At(time);
  in.brake = brake.At(time);
  in.clutch = clutch.At(time);
  in.gear = static_cast<int>(std::lround(gear.At(time)));
  in.steer = steer.At(time);
  return in;
}

double InputTables::EndTime() const {
  double end = 0.0;
  for (const Channel* c : {&throttle, &brake, &clutch, &gear, &steer}) {
    if (!c->t.empty()) end = std::max(end, c->t.back());
  }
  return end;
}

namespace {

Channel ParseChannel(YamlMap& map, const std::string& key, const Range& range, double scale,
                     bool hold, bool integer) {
  Channel channel;
  channel.hold = hold;
  YAML::Node knots = map.Sequence(key);
  const std::string field = map.FieldName(key);
  for (std::size_t i = 0; i < knots.size(); ++i) {
    const YAML::Node& knot = knots[i];
    const std::string name = field + "[" + std::to_string(i) + "]";
    if (!knot.IsSequence() || knot.size() != 2) {
      throw InputError(map.file().string(), LineOf(knot), name, "a pair [t_s, value]", "something else");
    }
    const double t = ScalarNumber(knot[0], map.file(), name + "[0]", Range::Closed(0.0, 1.0e6, "s"));
    const double v = ScalarNumber(knot[1], map.file(), name + "[1]", range);
    if (integer && v != std::round(v)) {
      throw InputError(map.file().string(), LineOf(knot), name + "[1]", "an integer", FormatDouble(v));
    }
    if (!channel.t.empty() && !(t > channel.t.back())) {
      throw InputError(map.file().string(), LineOf(knot), name + "[0]", "times rising strictly",
                       FormatDouble(t) + " after " + FormatDouble(channel.t.back()));
    }
    channel.t.push_back(t);
    channel.value.push_back(v * scale);
  }
  if (channel.t.empty()) {
    throw InputError(map.file().string(), map.LineOfKey(key), field, "at least one [t_s, value] knot", "none");
  }
  return channel;
}

}  // namespace

InputTables ParseInputTables(YamlMap& map, int gear_count) {
  InputTables tables;
  const Range unit = Range::Closed(0.0, 1.0);
  if (map.Has("throttle")) tables.throttle = ParseChannel(map, "throttle", unit, 1.0, false, false);
  if (map.Has("brake")) tables.brake = ParseChannel(map, "brake", unit, 1.0, false, false);
  if (map.Has("clutch")) tables.clutch = ParseChannel(map, "clutch", unit, 1.0, false, false);
  if (map.Has("gear")) {
    tables.gear = ParseChannel(map, "gear", Range::Closed(-1.0, gear_count), 1.0, true, true);
  }
  if (map.Has("steer_rad") && map.Has("steer_deg")) {
    map.Fail("steer_deg", "one of steer_rad or steer_deg", "both");
  }
  if (map.Has("steer_rad")) {
    tables.steer = ParseChannel(map, "steer_rad", Range::Closed(-20.0, 20.0, "rad"), 1.0, false, false);
  }
  if (map.Has("steer_deg")) {
    tables.steer = ParseChannel(map, "steer_deg", Range::Closed(-1200.0, 1200.0, "deg"), kPi / 180.0, false, false);
  }
  map.Finish();
  return tables;
}

InputTables ReadRecordedDrive(const std::filesystem::path& file, int gear_count) {
  const NumericCsv csv = ReadNumericCsv(
      file, {"t_s", "throttle", "brake", "clutch", "gear", "steer_rad"},
      [gear_count](std::size_t k, double value, const NumericCsv& so_far) -> std::string {
        const std::vector<double>& t = so_far.columns[0];
        if (k == 0 && !t.empty() && !(value > t.back())) return "t_s rising strictly";
        if ((k >= 1 && k <= 3) && (value < 0.0 || value > 1.0)) return "a number in [0, 1]";
        if (k == 4 && (value != std::round(value) || value < -1.0 || value > gear_count)) {
          return "an integer gear in [-1, " + std::to_string(gear_count) + "]";
        }
        return "";
      });
  InputTables tables;
  tables.gear.hold = true;
  Channel* channels[] = {nullptr, &tables.throttle, &tables.brake, &tables.clutch, &tables.gear, &tables.steer};
  for (std::size_t k = 1; k < csv.columns.size(); ++k) {
    channels[k]->t = csv.columns[0];
    channels[k]->value = csv.columns[k];
  }
  return tables;
}

std::string RecordedDriveCsv(const std::vector<double>& t, const std::vector<DriverInput>& inputs) {
  std::string text = "t_s,throttle,brake,clutch,gear,steer_rad\n";
  for (std::size_t k = 0; k < t.size() && k < inputs.size(); ++k) {
    const DriverInput& in = inputs[k];
    text += FormatDouble(t[k]) + "," + FormatDouble(in.throttle) + "," + FormatDouble(in.brake) + "," +
            FormatDouble(in.clutch) + "," + std::to_string(in.gear) + "," + FormatDouble(in.steer) + "\n";
  }
  return text;
}

PathDriver::PathDriver(PathDriverParams params, std::vector<PathPoint> path, std::vector<SpeedPoint> speed)
    : params_(params), path_(std::move(path)), speed_(std::move(speed)) {
  cumulative_.assign(path_.size(), 0.0);
  for (std::size_t i = 1; i < path_.size(); ++i) {
    cumulative_[i] = cumulative_[i - 1] + std::hypot(path_[i].x - path_[i - 1].x, path_[i].y - path_[i - 1].y);
  }
}

void PathDriver::StartRolling(int gear) {
  mode_ = gear > 0 ? Mode::kDrive : Mode::kStopped;
  clutch_ = gear > 0 ? 0.0 : 1.0;
  gear_ = gear;
  integral_ = 0.0;
}

double PathDriver::TargetSpeed(double s) const {
  if (speed_.empty()) return 0.0;
  if (s <= speed_.front().s) return speed_.front().v;
  if (s >= speed_.back().s) return speed_.back().v;
  std::size_t i = 1;
  while (speed_[i].s < s) ++i;
  const double w = (s - speed_[i - 1].s) / (speed_[i].s - speed_[i - 1].s);
  return speed_[i - 1].v + w * (speed_[i].v - speed_[i - 1].v);
}

PathPoint PathDriver::PointAt(double s) const {
  if (s <= 0.0) return path_.front();
  if (s >= cumulative_.back()) {
    // extend along the last segment
    const PathPoint& a = path_[path_.size() - 2];
    const PathPoint& b = path_.back();
    const double len = cumulative_.back() - cumulative_[cumulative_.size() - 2];
    const double w = (s - cumulative_[cumulative_.size() - 2]) / len;
    return {a.x + w * (b.x - a.x), a.y + w * (b.y - a.y)};
  }
  const std::size_t i = static_cast<std::size_t>(
      std::upper_bound(cumulative_.begin(), cumulative_.end(), s) - cumulative_.begin());
  const double w = (s - cumulative_[i - 1]) / (cumulative_[i] - cumulative_[i - 1]);
  return {path_[i - 1].x + w * (path_[i].x - path_[i - 1].x), path_[i - 1].y + w * (path_[i].y - path_[i - 1].y)};
}

DriverInput PathDriver::Step(const Vehicle& car, const VehicleState& state, double dt) {
  DriverInput in = Decide(car, state, dt);
  in.brake = std::min(in.brake, brake_ + params_.brake_rate * dt);  // a foot presses progressively
  brake_ = in.brake;
  const double step = params_.clutch_rate * dt;
  in.clutch = std::clamp(in.clutch, clutch_ - step, clutch_ + step);  // a foot moves the pedal in time
  clutch_ = in.clutch;
  return in;
}

DriverInput PathDriver::Decide(const Vehicle& car, const VehicleState& state, double dt) {
  // progress: nearest point on the segments around the last one
  {
    double best = std::numeric_limits<double>::infinity();
    const std::size_t lo = segment_ > 2 ? segment_ - 2 : 0;
    const std::size_t hi = std::min(path_.size() - 1, segment_ + 20);
    for (std::size_t i = lo; i < hi; ++i) {
      const PathPoint& a = path_[i];
      const PathPoint& b = path_[i + 1];
      const double dx = b.x - a.x, dy = b.y - a.y;
      const double len2 = dx * dx + dy * dy;
      const double w = std::clamp(((state.x - a.x) * dx + (state.y - a.y) * dy) / len2, 0.0, 1.0);
      const double px = a.x + w * dx, py = a.y + w * dy;
      const double d2 = (state.x - px) * (state.x - px) + (state.y - py) * (state.y - py);
      if (d2 < best) {
        best = d2;
        segment_ = i;
        progress_ = cumulative_[i] + w * std::sqrt(len2);
        lateral_error_ = (dx * (state.y - a.y) - dy * (state.x - a.x)) / std::sqrt(len2);
      }
    }
  }
  DriverInput in;
  // steering: pure pursuit on a look-ahead point
  {
    const double speed = std::max(0.0, state.u);
    const double ld = std::max(params_.min_preview, speed * params_.preview_time);
    const PathPoint target = PointAt(progress_ + ld);
    const double dx = target.x - state.x, dy = target.y - state.y;
    const double c = std::cos(state.yaw), s = std::sin(state.yaw);
    const double bx = c * dx + s * dy;
    const double by = -s * dx + c * dy;
    const double d2 = bx * bx + by * by;
    const double curvature = 2.0 * by / std::max(d2, 1e-6);
    const double delta = std::atan(car.chassis.wheelbase * curvature);
    in.steer = delta * car.steering.ratio;
  }
  // speed: PI on throttle, P on brake
  const double target = TargetSpeed(progress_);
  const double error = target - state.u;
  const double rpm = EngineRpm(state);
  const int top = params_.top_gear > 0 ? std::min(params_.top_gear, car.gear_count()) : car.gear_count();
  if (mode_ == Mode::kStopped) {
    in.brake = 0.3;
    in.clutch = 1.0;
    in.gear = 0;
    if (target > 0.5) {
      mode_ = Mode::kLaunch;
      gear_ = 1;
      timer_ = 0.0;
      integral_ = 0.0;
    }
    return in;
  }
  if (target < 1.5 && state.u < params_.stop_speed) {
    // slowing to a halt: clutch in, neutral once (almost) stopped, brake firmly
    in.clutch = 1.0;
    in.brake = std::clamp(0.3 + params_.brake_gain * -error, 0.0, params_.max_brake);
    in.gear = gear_;
    if (state.u < 0.05 && target <= 0.5) {
      mode_ = Mode::kStopped;
      gear_ = 0;
      in.gear = 0;
    }
    return in;
  }
  if (mode_ == Mode::kLaunch) {
    timer_ += dt;
    in.gear = 1;
    in.throttle = std::clamp(0.15 + 0.002 * (params_.launch_rpm - rpm), 0.0, 1.0);
    const double u = std::clamp(timer_ / params_.launch_time, 0.0, 1.0);
    const double free = car.clutch.free_pedal;
    in.clutch = free * (1.0 - u);
    if (u >= 1.0) {
      mode_ = Mode::kDrive;
      integral_ = 0.0;
    }
    return in;
  }
  if (mode_ == Mode::kShift) {
    timer_ += dt;
    const double press = 0.25 * params_.shift_time;
    in.gear = timer_ < press ? gear_ : next_gear_;
    if (timer_ < press) {
      in.clutch = 1.0;
    } else {
      const double u = std::clamp((timer_ - press) / (params_.shift_time - press), 0.0, 1.0);
      in.clutch = car.clutch.free_pedal * (1.0 - u);
    }
    in.throttle = timer_ < press ? 0.0 : std::clamp(params_.speed_gain * error + params_.speed_integral * integral_, 0.0, 1.0);
    if (timer_ >= params_.shift_time) {
      gear_ = next_gear_;
      mode_ = Mode::kDrive;
    }
    return in;
  }
  // drive: throttle (PI) within the dead band below the target, brake (P) beyond it, the brake
  // growing from 0 at the band's edge so that the feet never chatter between the pedals
  in.gear = gear_;
  if (error >= -params_.brake_band) {
    integral_ = std::clamp(integral_ + error * dt, 0.0, 1.0 / std::max(params_.speed_integral, 1e-9));
    in.throttle = std::clamp(params_.speed_gain * error + params_.speed_integral * integral_, 0.0, 1.0);
  } else {
    integral_ = 0.0;
    in.brake = std::clamp(params_.brake_gain * (-error - params_.brake_band), 0.0, params_.max_brake);
  }
  if (rpm > params_.upshift_rpm && gear_ < top) {
    mode_ = Mode::kShift;
    next_gear_ = gear_ + 1;
    timer_ = 0.0;
  } else if (rpm < params_.downshift_rpm && gear_ > 2) {
    mode_ = Mode::kShift;
    next_gear_ = gear_ - 1;
    timer_ = 0.0;
  } else if (rpm < params_.downshift_rpm && gear_ == 2) {
    if (target > state.u + params_.brake_band) {  // pulling away again: back to first
      mode_ = Mode::kShift;
      next_gear_ = 1;
      timer_ = 0.0;
    } else {
      in.clutch = 1.0;  // slowing down in second: coast with the clutch in, as drivers do
      in.throttle = 0.0;
    }
  } else if (gear_ == 1 && rpm < 0.5 * (car.engine.idle_rpm + car.engine.stall_rpm) + 200.0) {
    in.clutch = car.clutch.free_pedal;  // would stall in first: slip the clutch
  }
  return in;
}

LaneChangeTrack MakeIso3888Track(double width, double x0, double run_in, double run_out) {
  LaneChangeTrack track;
  const double w1 = 1.1 * width + 0.25;
  const double w3 = 1.2 * width + 0.25;
  const double w5 = 1.3 * width + 0.25;
  // x of each section's start; y of the right cone row of sections 1, 3, 5 (section 1 centred on y = 0)
  const double xs[] = {x0, x0 + 15.0, x0 + 45.0, x0 + 70.0, x0 + 95.0, x0 + 110.0, x0 + 125.0};
  const double r1 = -0.5 * w1;
  const double r3 = r1 + 3.5;
  const double r5 = r1;
  auto gate = [&](double xa, double xb, double right, double lane) {
    for (double x : {xa, 0.5 * (xa + xb), xb}) {
      track.right_cones.push_back({x, right});
      track.left_cones.push_back({x, right + lane});
    }
  };
  gate(xs[0], xs[1], r1, w1);
  gate(xs[2], xs[3], r3, w3);
  gate(xs[4], xs[6], r5, w5);
  const double c1 = 0.0;
  const double c3 = r3 + 0.5 * w3;
  const double c5 = r5 + 0.5 * w5;
  track.lane_offset = c3 - c1;
  track.x_start = xs[0];
  track.x_end = xs[6];
  // centre path: straight in the gates, cosine transitions between them, sampled every 0.5 m
  auto centre_y = [&](double x) {
    auto blend = [](double ya, double yb, double xa, double xb, double xx) {
      const double u = std::clamp((xx - xa) / (xb - xa), 0.0, 1.0);
      return ya + (yb - ya) * 0.5 * (1.0 - std::cos(kPi * u));
    };
    if (x <= xs[1]) return c1;
    if (x <= xs[2]) return blend(c1, c3, xs[1], xs[2], x);
    if (x <= xs[3]) return c3;
    if (x <= xs[4]) return blend(c3, c5, xs[3], xs[4], x);
    return c5;
  };
  for (double x = x0 - run_in; x <= xs[6] + run_out + 1e-9; x += 0.5) {
    track.centre.push_back({x, centre_y(x)});
  }
  return track;
}

}  // namespace pwsim::vehicle
