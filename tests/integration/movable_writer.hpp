// SPDX-License-Identifier: Apache-2.0
// A test's DataWriter on a publisher of its own, so that it can be moved into other partitions
// after it was created. DDS Security checks a writer's partitions locally once, at creation: a
// participant whose own checks were skipped (a modified library) could announce any partition,
// and set_qos is how a test announces one; the other participants must refuse it themselves.
#pragma once

#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/participant.hpp"

#include <fastdds/dds/publisher/qos/PublisherQos.hpp>

#include <chrono>
#include <string>
#include <vector>

namespace ncqual::testing {

class MovableWriter {
 public:
  // A writer of `topic` with the QoS profile `profile`, in `partitions` ({}: the default one);
  // created() says whether the participant's permissions allowed it.
  MovableWriter(dds::Participant& p, eprosima::fastdds::dds::Topic* topic, const char* profile,
                const std::vector<std::string>& partitions)
      : participant_(p) {
    eprosima::fastdds::dds::PublisherQos qos = eprosima::fastdds::dds::PUBLISHER_QOS_DEFAULT;
    for (const auto& name : partitions) qos.partition().push_back(name.c_str());
    publisher_ = p.get()->create_publisher(qos);
    eprosima::fastdds::dds::DataWriterQos wq = eprosima::fastdds::dds::DATAWRITER_QOS_DEFAULT;
    publisher_->get_datawriter_qos_from_profile(profile, wq);
    writer_ = publisher_->create_datawriter(topic, wq);
  }
  ~MovableWriter() {
    if (writer_) publisher_->delete_datawriter(writer_);
    participant_.get()->delete_publisher(publisher_);
  }
  MovableWriter(const MovableWriter&) = delete;
  MovableWriter& operator=(const MovableWriter&) = delete;

  bool created() const { return writer_ != nullptr; }
  eprosima::fastdds::dds::DataWriter* get() const { return writer_; }

  // Into `partitions`; {} is the default partition, named explicitly (""): an update whose list
  // is empty carries no partition at all in Fast DDS 2.9.1, and the other participants keep the
  // partitions they knew (the writer stays where it may write).
  bool move_to(const std::vector<std::string>& partitions) {
    eprosima::fastdds::dds::PublisherQos qos = publisher_->get_qos();
    qos.partition().clear();
    for (const auto& name : partitions) qos.partition().push_back(name.c_str());
    if (partitions.empty()) qos.partition().push_back("");
    return publisher_->set_qos(qos) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK;
  }
  int matched_readers() const {
    eprosima::fastdds::dds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return status.current_count;
  }
  bool wait_for_readers(int n, std::chrono::milliseconds timeout) {
    return dds::wait_until_matched(
        writer_->get_statuscondition(), eprosima::fastdds::dds::StatusMask::publication_matched(),
        [this] { return matched_readers(); }, n, timeout);
  }

 private:
  dds::Participant& participant_;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

}  // namespace ncqual::testing
