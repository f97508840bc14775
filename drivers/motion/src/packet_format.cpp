#include "vifusion/motion/packet_format.hpp"

namespace vifusion::motion {

std::string_view eventSourceName(EventSource source) {
  switch (source) {
    case EventSource::kAccelerometer:
      return "accelerometer";
    case EventSource::kGyroscope:
      return "gyroscope";
    case EventSource::kDepthFrame:
      return "depth_frame";
    case EventSource::kFisheyeFrame:
      return "fisheye_frame";
    case EventSource::kGpio0:
      return "gpio0";
    case EventSource::kGpio1:
      return "gpio1";
    case EventSource::kGpio2:
      return "gpio2";
  }
  return "invalid";  // code 0, or any value cast in from the wire
}

std::string_view errorFlagName(ErrorFlag flag) {
  switch (flag) {
    case ErrorFlag::kImuNotResponding:
      return "imu_not_responding";
    case ErrorFlag::kIllegalConfiguration:
      return "illegal_configuration";
    case ErrorFlag::kTimestampFifoOverflow:
      return "timestamp_fifo_overflow";
    case ErrorFlag::kImuFifoOverflow:
      return "imu_fifo_overflow";
    case ErrorFlag::kWatchdogReset:
      return "watchdog_reset";
    case ErrorFlag::kCrcError:
      return "crc_error";
    case ErrorFlag::kMissingDataFromImu:
      return "missing_data_from_imu";
    case ErrorFlag::kBootloaderFailure:
      return "bootloader_failure";
    case ErrorFlag::kEepromError:
      return "eeprom_error";
    case ErrorFlag::kBuiltInSelfTestFailed:
      return "built_in_self_test_failed";
    case ErrorFlag::kMicrocontrollerNotResponding:
      return "microcontroller_not_responding";
    case ErrorFlag::kCx3FifoOverflow:
      return "cx3_fifo_overflow";
    case ErrorFlag::kCx3GeneralFailure:
      return "cx3_general_failure";
    case ErrorFlag::kCx3UsbFailure:
      return "cx3_usb_failure";
    case ErrorFlag::kReserved14:
      return "reserved_bit_14";
    case ErrorFlag::kReserved15:
      return "reserved_bit_15";
  }
  return "unknown_flag";
}

}  // namespace vifusion::motion
