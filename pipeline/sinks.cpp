#include "pipeline/sinks.h"

namespace vts {

ExrSink::ExrSink(std::filesystem::path path, ExrCompression compression)
    : path_(std::move(path)), compression_(compression) {}
ExrSink::~ExrSink() = default;

void ExrSink::begin(const ProfileFileInfo& info) {
  writer_ = std::make_unique<ProfileExrWriter>(path_, info, compression_);
}

void ExrSink::write(const ScanBatch& batch) {
  for (std::size_t k = 0; k < batch.profiles.size(); ++k)
    writer_->write(batch.profiles[k], batch.reference.empty() ? nullptr : &batch.reference[k]);
}

void ExrSink::finish() { writer_->finish(); }

void MemorySink::begin(const ProfileFileInfo& info) {
  recording = ProfileRecording{};
  recording.info = info;
  recording.profiles.reserve(static_cast<std::size_t>(info.profiles));
  if (info.has_reference) recording.reference.reserve(static_cast<std::size_t>(info.profiles));
}

void MemorySink::write(const ScanBatch& batch) {
  recording.profiles.insert(recording.profiles.end(), batch.profiles.begin(), batch.profiles.end());
  recording.reference.insert(recording.reference.end(), batch.reference.begin(), batch.reference.end());
}

}  // namespace vts
