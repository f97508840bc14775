// SyncReport::toJson(): one JSON object, keys in this fixed order, units in the key names (_ns
// nanoseconds, _ppm parts per million, _hz hertz, fraction in [0, 1]); unmeasured numbers are null.
//   passed                 bool: every check passed (the CLI's exit code 0)
//   failed_checks          [name]: the failed checks' names
//   checks                 [{name, passed, value, limit, unit, detail}]: value and limit in unit
//   frames                 {count, paired_with_edge, without_edge, with_device_event, stamped_by_device_event,
//                           stamped_by_kernel, out_of_order, frame_number_backwards, frame_numbers_present,
//                           rate_hz}
//   edges                  {polarity ("rising"/"falling"), count, used, out_of_order, lost_by_driver, period_ns}
//   dropped                {edges_without_frame, frame_number_gaps, dropped, fraction}
//   duplicated             {frames_on_one_edge, repeated_frame_numbers}
//   streams                {<stream name>: {count, offset_mean_ns, offset_median_ns, offset_at_first_ns,
//                           drift_ppm, jitter_std_ns, jitter_p99_ns, jitter_max_ns}} for frame_minus_edge,
//                           kernel_minus_edge, device_event_minus_edge, frame_minus_kernel (a − b)
//   imu                    {samples, rate_hz, mean_rate_hz, median_dt_ns, gaps, largest_gap_ns, out_of_order}
//   clock_mapper           {samples, non_finite, residual_mean_ns, residual_std_ns, residual_p99_abs_ns,
//                           residual_max_abs_ns}
//   problems               [text]: the first pieces of bad input, each naming its record
#include <nlohmann/json.hpp>

#include "vifusion/synccheck/sync_report.hpp"

namespace vifusion::synccheck {
namespace {

using Json = nlohmann::ordered_json;

Json streamJson(const StreamStats& s) {
  return Json{{"count", s.count},
              {"offset_mean_ns", s.offset_mean_ns},
              {"offset_median_ns", s.offset_median_ns},
              {"offset_at_first_ns", s.offset_at_first_ns},
              {"drift_ppm", s.drift_ppm},
              {"jitter_std_ns", s.jitter_std_ns},
              {"jitter_p99_ns", s.jitter_p99_ns},
              {"jitter_max_ns", s.jitter_max_ns}};
}

}  // namespace

std::string SyncReport::toJson() const {
  Json json;
  json["passed"] = passed;
  json["failed_checks"] = failedChecks();
  Json check_list = Json::array();
  for (const CheckResult& c : checks) {
    check_list.push_back(Json{{"name", c.name},
                              {"passed", c.passed},
                              {"value", c.value},
                              {"limit", c.limit},
                              {"unit", c.unit},
                              {"detail", c.detail}});
  }
  json["checks"] = check_list;
  json["frames"] = Json{{"count", frames.count},
                        {"paired_with_edge", frames.paired_with_edge},
                        {"without_edge", frames.without_edge},
                        {"with_device_event", frames.with_device_event},
                        {"stamped_by_device_event", frames.stamped_by_device_event},
                        {"stamped_by_kernel", frames.stamped_by_kernel},
                        {"out_of_order", frames.out_of_order},
                        {"frame_number_backwards", frames.frame_number_backwards},
                        {"frame_numbers_present", frames.frame_numbers_present},
                        {"rate_hz", frames.rate_hz}};
  json["edges"] = Json{{"polarity", edgePolarityName(edges.polarity)},
                       {"count", edges.count},
                       {"used", edges.used},
                       {"out_of_order", edges.out_of_order},
                       {"lost_by_driver", edges.lost_by_driver},
                       {"period_ns", edges.period_ns}};
  json["dropped"] = Json{{"edges_without_frame", dropped.edges_without_frame},
                         {"frame_number_gaps", dropped.frame_number_gaps},
                         {"dropped", dropped.dropped},
                         {"fraction", dropped.fraction}};
  json["duplicated"] = Json{{"frames_on_one_edge", duplicated.frames_on_one_edge},
                            {"repeated_frame_numbers", duplicated.repeated_frame_numbers}};
  Json stream_map = Json::object();
  for (const StreamStats& s : streams) stream_map[s.name] = streamJson(s);
  json["streams"] = stream_map;
  json["imu"] =
      Json{{"samples", imu.samples},           {"rate_hz", imu.rate_hz}, {"mean_rate_hz", imu.mean_rate_hz},
           {"median_dt_ns", imu.median_dt_ns}, {"gaps", imu.gaps},       {"largest_gap_ns", imu.largest_gap_ns},
           {"out_of_order", imu.out_of_order}};
  json["clock_mapper"] = Json{{"samples", clock_residuals.samples},
                              {"non_finite", clock_residuals.non_finite},
                              {"residual_mean_ns", clock_residuals.mean_ns},
                              {"residual_std_ns", clock_residuals.std_ns},
                              {"residual_p99_abs_ns", clock_residuals.p99_abs_ns},
                              {"residual_max_abs_ns", clock_residuals.max_abs_ns}};
  json["problems"] = problems;
  return json.dump();
}

}  // namespace vifusion::synccheck
