#pragma once
// OpenCascade's data-exchange writers report their statistics ("Statistics on Transfer
// (Write)", "Step File Name : ... Write Done") through the default messenger, whose printer writes
// to std::cout. A library must not write to the caller's stdout (scripts parse it, `--quiet`
// promises silence); failures reach us as return codes and exceptions instead. This detaches the
// messenger's printers for a scope and puts them back afterwards.
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_SequenceOfPrinters.hxx>

namespace isospring::geometry::detail {

class SilenceOpenCascade {
 public:
  SilenceOpenCascade() : saved_(Message::DefaultMessenger()->Printers()) {
    Message::DefaultMessenger()->ChangePrinters().Clear();
  }
  ~SilenceOpenCascade() { Message::DefaultMessenger()->ChangePrinters() = saved_; }
  SilenceOpenCascade(const SilenceOpenCascade&) = delete;
  SilenceOpenCascade& operator=(const SilenceOpenCascade&) = delete;

 private:
  Message_SequenceOfPrinters saved_;
};

}  // namespace isospring::geometry::detail
