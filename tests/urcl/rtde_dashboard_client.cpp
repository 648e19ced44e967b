// Clients of RTDE and the dashboard server built on UR's own client library (URCL), as a driver
// uses them: RTDEClient negotiates the protocol, reads the controller version, sets up an output
// recipe at FREQUENCY and an input recipe, starts and reads COUNT data packages; DashboardClient
// connects, reads the banner and sends a few commands. It prints what URCL read as one JSON object
// per line. Any warning or error URCL logs is printed as {"urcl_log": ...}.
//
// usage: rtde_dashboard_client HOST RTDE_PORT FREQUENCY COUNT (the dashboard on HOST's port 29999)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include <ur_client_library/comm/pipeline.h>
#include <ur_client_library/log.h>
#include <ur_client_library/rtde/rtde_client.h>
#include <ur_client_library/ur/dashboard_client.h>

using namespace urcl;

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

void printVector6(const char* name, const vector6d_t& values)
{
  std::printf(", \"%s\": [", name);
  for (size_t i = 0; i < values.size(); ++i)
    std::printf(i ? ", %.17g" : "%.17g", values[i]);
  std::printf("]");
}
}  // namespace

int main(int argc, char** argv)
{
  if (argc != 5)
  {
    std::fprintf(stderr, "usage: %s HOST RTDE_PORT FREQUENCY COUNT\n", argv[0]);
    return 2;
  }
  const std::string host = argv[1];
  const uint32_t rtde_port = static_cast<uint32_t>(std::atoi(argv[2]));
  const double frequency = std::atof(argv[3]);
  const int count = std::atoi(argv[4]);
  registerLogHandler(std::make_unique<PrintingLogHandler>());
  setLogLevel(LogLevel::WARN);

  comm::INotifier notifier;
  const std::vector<std::string> outputs = { "timestamp", "actual_q", "actual_TCP_pose", "robot_mode",
                                             "runtime_state" };
  const std::vector<std::string> inputs = { "speed_slider_mask", "speed_slider_fraction" };
  rtde_interface::RTDEClient client(host, notifier, outputs, inputs, frequency, false, rtde_port);
  if (!client.init(3, std::chrono::milliseconds(500)))
  {
    std::printf("{\"error\": \"init\"}\n");
    return 1;
  }
  const VersionInformation version = client.getVersion();
  std::printf("{\"type\": \"version\", \"major\": %u, \"minor\": %u, \"bugfix\": %u, \"build\": %u, "
              "\"frequency\": %.17g}\n",
              version.major, version.minor, version.bugfix, version.build, client.getTargetFrequency());
  if (!client.start(false))
  {
    std::printf("{\"error\": \"start\"}\n");
    return 1;
  }
  // Pre-allocated, as URCL asks: its parser fills the package of the client's recipe (protocol 2,
  // which the client negotiated).
  auto package = std::make_unique<rtde_interface::DataPackage>(client.getOutputRecipe());
  for (int i = 0; i < count; ++i)
  {
    if (!client.getDataPackageBlocking(package))
    {
      std::printf("{\"error\": \"data package %d\"}\n", i);
      return 1;
    }
    double timestamp = 0;
    vector6d_t q{}, pose{};
    int32_t robot_mode = 0;
    uint32_t runtime_state = 0;
    bool ok = package->getData("timestamp", timestamp) && package->getData("actual_q", q) &&
              package->getData("actual_TCP_pose", pose) && package->getData("robot_mode", robot_mode) &&
              package->getData("runtime_state", runtime_state);
    if (!ok)
    {
      std::printf("{\"error\": \"getData\"}\n");
      return 1;
    }
    std::printf("{\"type\": \"data_package\", \"timestamp\": %.17g", timestamp);
    printVector6("actual_q", q);
    printVector6("actual_TCP_pose", pose);
    std::printf(", \"robot_mode\": %d, \"runtime_state\": %u}\n", robot_mode, runtime_state);
  }
  const bool sent = client.getWriter().sendSpeedSlider(0.5);
  std::printf("{\"type\": \"speed_slider\", \"sent\": %s}\n", sent ? "true" : "false");
  client.pause();

  DashboardClient dashboard(host);
  if (!dashboard.connect(3, std::chrono::milliseconds(500)))
  {
    std::printf("{\"error\": \"dashboard connect\"}\n");
    return 1;
  }
  for (const char* command : { "PolyscopeVersion", "robotmode", "programState", "stop", "programState" })
    std::printf("{\"type\": \"dashboard\", \"command\": \"%s\", \"reply\": \"%s\"}\n", command,
                dashboard.sendAndReceive(command).c_str());
  dashboard.disconnect();
  return 0;
}
