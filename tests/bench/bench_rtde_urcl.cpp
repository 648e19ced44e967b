// URCL's reader for tests/bench/bench_rtde_hot.c: the package parsed by RTDEParser::parse into a
// preallocated DataPackage (URCL's real-time path, no allocation per package), then getData of
// every value by its name and type, added up as the other readers add theirs.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ur_client_library/comm/bin_parser.h"
#include "ur_client_library/rtde/data_package.h"
#include "ur_client_library/rtde/rtde_parser.h"

namespace rtde = urcl::rtde_interface;

static double six(const urcl::vector6d_t& v)
{
  return v[0] + v[1] + v[2] + v[3] + v[4] + v[5];
}

extern "C" double urcl_read(const uint8_t* package, size_t size, long packages, const char* const* names,
                            size_t count)
{
  std::vector<std::string> recipe(names, names + count);
  rtde::RTDEParser parser(recipe);
  parser.setProtocolVersion(2);
  std::unique_ptr<rtde::RTDEPackage> result(new rtde::DataPackage(recipe, 2));
  std::vector<uint8_t> buffer(package, package + size);
  double sum = 0;
  for (long p = 0; p < packages; p++)
  {
    urcl::comm::BinParser bp(buffer.data(), buffer.size());
    if (!parser.parse(bp, result))
      return -1;
    const auto& d = *static_cast<rtde::DataPackage*>(result.get());
    double timestamp, speed_scaling;
    urcl::vector6d_t q, qd, pose, force, temperatures;
    int32_t robot_mode, safety_mode, register0;
    uint32_t runtime_state;
    uint64_t inputs;
    bool ok = d.getData("timestamp", timestamp) && d.getData("actual_q", q) && d.getData("actual_qd", qd) &&
              d.getData("actual_TCP_pose", pose) && d.getData("actual_TCP_force", force) &&
              d.getData("robot_mode", robot_mode) && d.getData("safety_mode", safety_mode) &&
              d.getData("runtime_state", runtime_state) && d.getData("actual_digital_input_bits", inputs) &&
              d.getData("speed_scaling", speed_scaling) && d.getData("output_int_register_0", register0) &&
              d.getData("joint_temperatures", temperatures);
    if (!ok)
      return -1;
    sum += timestamp + six(q) + six(qd) + six(pose) + six(force) + robot_mode + safety_mode +
           static_cast<double>(runtime_state) + static_cast<double>(inputs) + speed_scaling + register0 +
           six(temperatures);
  }
  return sum;
}
