// A client of the primary interface built on UR's own client library (URCL): it connects as a
// driver does (URStream frames by the header's length, PrimaryParser parses in strict mode, so a
// sub-package not read to its end is an error), reads COUNT messages and prints what URCL decoded
// as one JSON object per line. Any warning or error URCL logs is printed as {"urcl_log": ...}.
//
// usage: primary_client HOST PORT COUNT
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <ur_client_library/comm/stream.h>
#include <ur_client_library/log.h>
#include <ur_client_library/primary/primary_parser.h>

using namespace urcl;
using namespace urcl::primary_interface;

namespace
{
class PrintingLogHandler : public LogHandler
{
public:
  void log(const char* file, int line, LogLevel level, const char* text) override
  {
    if (level >= LogLevel::WARN)
      std::printf("{\"urcl_log\": \"%d %s:%d\", \"text\": \"%s\"}\n", static_cast<int>(level), file, line, text);
  }
};

template <typename T>
void printArray(const char* name, const T& values)
{
  std::printf(", \"%s\": [", name);
  for (size_t i = 0; i < values.size(); ++i)
    std::printf(i ? ", %.17g" : "%.17g", static_cast<double>(values[i]));
  std::printf("]");
}

void print(const PrimaryPackage& package)
{
  if (auto* v = dynamic_cast<const VersionMessage*>(&package))
  {
    // URCL keeps the field after the minor version as svn_version_: the bugfix version from 3.3.
    std::printf("{\"type\": \"version\", \"project_name\": \"%s\", \"major_version\": %d, \"minor_version\": %d, "
                "\"bugfix_version\": %d, \"build_number\": %d}\n",
                v->project_name_.c_str(), v->major_version_, v->minor_version_, v->svn_version_, v->build_number_);
  }
  else if (auto* k = dynamic_cast<const KinematicsInfo*>(&package))
  {
    std::printf("{\"type\": \"kinematics_info\"");
    printArray("checksum", k->checksum_);
    printArray("dh_theta", k->dh_theta_);
    printArray("dh_a", k->dh_a_);
    printArray("dh_d", k->dh_d_);
    printArray("dh_alpha", k->dh_alpha_);
    std::printf(", \"calibration_status\": %u}\n", k->calibration_status_);
  }
  else if (auto* c = dynamic_cast<const ConfigurationData*>(&package))
  {
    std::printf("{\"type\": \"configuration_data\"");
    printArray("dh_a", c->dh_a_);
    printArray("dh_d", c->dh_d_);
    printArray("dh_alpha", c->dh_alpha_);
    printArray("dh_theta", c->dh_theta_);
    std::printf(", \"masterboard_version\": %d, \"controller_box_type\": %d, \"robot_type\": %d, "
                "\"robot_sub_type\": %d}\n",
                c->masterboard_version_, c->controller_box_type_, c->robot_type_, c->robot_sub_type_);
  }
  else if (auto* m = dynamic_cast<const RobotModeData*>(&package))
  {
    std::printf("{\"type\": \"robot_mode_data\", \"timestamp\": %llu, \"robot_mode\": %d, \"control_mode\": %d, "
                "\"is_protective_stopped\": %s, \"target_speed_fraction\": %.17g}\n",
                static_cast<unsigned long long>(m->timestamp_), m->robot_mode_, m->control_mode_,
                m->is_protective_stopped_ ? "true" : "false", m->target_speed_fraction_);
  }
  else if (auto* b = dynamic_cast<const MasterboardData*>(&package))
  {
    std::printf("{\"type\": \"masterboard_data\", \"safety_mode\": %d, \"master_board_temperature\": %.17g}\n",
                static_cast<int>(b->safety_mode_), static_cast<double>(b->master_board_temperature_));
  }
  else if (auto* s = dynamic_cast<const SafetyModeMessage*>(&package))
  {
    std::printf("{\"type\": \"safety_mode\", \"safety_mode_type\": %d}\n", static_cast<int>(s->safety_mode_type_));
  }
  else if (auto* key = dynamic_cast<const KeyMessage*>(&package))
  {
    std::printf("{\"type\": \"key\", \"title\": \"%s\"}\n", key->title_.c_str());
  }
}
}  // namespace

int main(int argc, char* argv[])
{
  if (argc != 4)
  {
    std::fprintf(stderr, "usage: %s HOST PORT COUNT\n", argv[0]);
    return 2;
  }
  registerLogHandler(std::make_unique<PrintingLogHandler>());
  setLogLevel(LogLevel::WARN);

  comm::URStream<PrimaryPackage> stream(argv[1], std::stoi(argv[2]));
  if (!stream.connect(3))
    return 1;
  PrimaryParser parser;
  parser.setStrictMode(true);

  std::vector<uint8_t> buffer(1 << 16);
  for (int n = std::stoi(argv[3]); n > 0; --n)
  {
    size_t length = 0;
    if (!stream.read(buffer.data(), buffer.size(), length))
      return 1;
    comm::BinParser bp(buffer.data(), length);
    std::vector<std::unique_ptr<PrimaryPackage>> packages;
    if (!parser.parse(bp, packages))
    {
      std::printf("{\"urcl_log\": \"parse\", \"text\": \"PrimaryParser::parse returned false\"}\n");
      return 1;
    }
    for (const auto& package : packages)
      print(*package);
  }
  std::fflush(stdout);
  return 0;
}
