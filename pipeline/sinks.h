#pragma once
// Sinks for scan jobs (pipeline/scan_job.h): a vts profile EXR file, and
// memory (for the Python package and tests); a network stream implements
// ScanSink itself.
#include <filesystem>
#include <functional>
#include <memory>

#include "pipeline/scan_job.h"
#include "sensor/profile_exr.h"

namespace vts {

// Writes the job to a profile EXR (docs/EXR_FORMAT.md) through a temporary
// file renamed by finish(): a failed or cancelled job leaves nothing under
// `path`. Missing directories are created. `compression`: how the file is
// compressed (lossless, sensor/profile_exr.h; ZIP unless asked).
class ExrSink final : public ScanSink {
 public:
  explicit ExrSink(std::filesystem::path path, ExrCompression compression = ExrCompression::Zip);
  ~ExrSink() override;
  void begin(const ProfileFileInfo& info) override;
  void write(const ScanBatch& batch) override;
  void finish() override;

 private:
  std::filesystem::path path_;
  ExrCompression compression_;
  std::unique_ptr<ProfileExrWriter> writer_;
};

// Keeps every profile (all channels, the ideal points too), in the form
// read_profile_exr returns a file.
class MemorySink final : public ScanSink {
 public:
  void begin(const ProfileFileInfo& info) override;
  void write(const ScanBatch& batch) override;
  void finish() override {}
  ProfileRecording recording;
};

// Calls `on_batch` with every batch (a stream to a client, a consumer that
// tracks as it goes); the profiles are valid during the call only.
class CallbackSink final : public ScanSink {
 public:
  explicit CallbackSink(std::function<void(const ScanBatch&)> on_batch) : on_batch_(std::move(on_batch)) {}
  void begin(const ProfileFileInfo&) override {}
  void write(const ScanBatch& batch) override { on_batch_(batch); }
  void finish() override {}

 private:
  std::function<void(const ScanBatch&)> on_batch_;
};

}  // namespace vts
