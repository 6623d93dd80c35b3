#include "bakers/bake_jobs.h"

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "files/input_record.h"
#include "files/utf8_path.h"

namespace ahd {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// Keys naming files: resolved against the job file's folder (a preset name stays a name).
bool is_path_key(const std::string& key, const std::string& value) {
  if (key == "layout") return value.size() > 5 && value.compare(value.size() - 5, 5, ".json") == 0;
  return key == "input" || key == "mesh" || key == "normals" || key == "placement" || key == "godot-scene";
}

void set_option(const std::string& path, size_t index, const std::string& key, const json& v, BakeInput* in) {
  const std::string where = "job " + std::to_string(index) + ": \"" + key + "\"";
  const fs::path dir = fs_path(path).parent_path();
  for (const BakeInputOption& o : bake_input_options()) {
    if (std::string(o.flag) != "--" + key) continue;
    if (auto* s = std::get_if<std::string BakeInput::*>(&o.field)) {
      if (!v.is_string()) throw file_error(path, where + " takes a string");
      const std::string value = v.get<std::string>();
      in->*(*s) = is_path_key(key, value) && fs_path(value).is_relative() ? utf8_string(dir / fs_path(value)) : value;
    } else if (auto* i = std::get_if<int BakeInput::*>(&o.field)) {
      if (!v.is_number_integer() || v.get<long long>() < o.min_value || v.get<long long>() > 1000000)
        throw file_error(path, where + " takes an integer of at least " + std::to_string(o.min_value));
      in->*(*i) = v.get<int>();
    } else if (auto* b = std::get_if<bool BakeInput::*>(&o.field)) {
      if (!v.is_boolean()) throw file_error(path, where + " takes true or false");
      in->*(*b) = v.get<bool>();
    }
    return;
  }
  std::string known = "input, output";
  for (const BakeInputOption& o : bake_input_options()) known += std::string(", ") + (o.flag + 2);
  throw file_error(path, where + " is not a job key (" + known + ")");
}

}  // namespace

std::vector<BakeJob> read_bake_jobs(const std::string& path, const BakeInput& defaults) {
  std::ifstream f(fs_path(path), std::ios::binary);
  if (!f) throw file_error(path, "file not found");
  note_input_file(path);
  json j;
  try {
    j = json::parse(f);
  } catch (const json::exception& e) {
    throw file_error(path, std::string("malformed job file (") + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("jobs") || !j["jobs"].is_array() || j["jobs"].empty())
    throw file_error(path, "expected {\"jobs\": [{\"input\": …}, …]} with at least one job");
  std::vector<BakeJob> jobs;
  for (size_t k = 0; k < j["jobs"].size(); ++k) {
    const json& o = j["jobs"][k];
    if (!o.is_object() || !o.contains("input") || !o["input"].is_string())
      throw file_error(path, "job " + std::to_string(k) + ": needs \"input\" (a lightmap file)");
    BakeJob job;
    job.input = defaults;
    job.input.notes.clear();
    job.input.input = utf8_string(fs_path(path).parent_path() / fs_path(o["input"].get<std::string>()));
    if (fs_path(o["input"].get<std::string>()).is_absolute()) job.input.input = o["input"].get<std::string>();
    for (auto it = o.begin(); it != o.end(); ++it) {
      if (it.key() == "input") continue;
      if (it.key() == "output") {
        if (!it.value().is_string() || it.value().get<std::string>().empty() ||
            it.value().get<std::string>().find('/') != std::string::npos)
          throw file_error(path, "job " + std::to_string(k) + ": \"output\" takes a name without folder");
        job.output = it.value().get<std::string>();
        continue;
      }
      set_option(path, k, it.key(), it.value(), &job.input);
    }
    if (job.output.empty()) job.output = utf8_string(fs_path(job.input.input).stem());
    jobs.push_back(std::move(job));
  }
  return jobs;
}

}  // namespace ahd
