// A minimal HTTP/1.1 client for the live server's tests and bench: plain
// POSIX sockets (httplib stays inside lab/live), a GET, the chunked body
// decoded, and the Server-Sent Events in it parsed. A client may also never
// read (a stalled browser) or close early (a browser that went away).
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace syrof::lab::live::testing {

struct SseEvent {
  std::string name;  // "message" when the event has no name
  std::string data;
  std::string id;
};

class SseClient {
 public:
  SseClient() = default;
  SseClient(const SseClient&) = delete;
  SseClient& operator=(const SseClient&) = delete;
  ~SseClient() { Close(); }

  /// Connects to 127.0.0.1:`port` and sends GET `path`. `receive_buffer`
  /// (bytes, 0: the system's) makes a small window for a stalled client.
  bool Get(int port, const std::string& path, int receive_buffer = 0, const std::string& host = "127.0.0.1") {
    fd_ = socket(AF_INET, SOCK_STREAM, 0);
    if (fd_ < 0) return false;
    if (receive_buffer > 0) setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) return false;
    const std::string request = "GET " + path + " HTTP/1.1\r\nHost: " + host + "\r\nAccept: text/event-stream\r\n\r\n";
    return send(fd_, request.data(), request.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(request.size());
  }

  void Close() {
    if (fd_ >= 0) close(fd_);
    fd_ = -1;
  }

  /// Reads until `done(events so far)` or `timeout`; false on timeout or
  /// when the server closed first.
  template <typename Done>
  bool ReadUntil(Done done, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!done(events_)) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return false;
      pollfd poll_fd{fd_, POLLIN, 0};
      if (poll(&poll_fd, 1, static_cast<int>(left.count())) <= 0) continue;
      char buffer[65536];
      const ssize_t got = recv(fd_, buffer, sizeof buffer, 0);
      if (got <= 0) {
        closed_ = true;
        return done(events_);
      }
      raw_.append(buffer, static_cast<size_t>(got));
      Parse();
    }
    return true;
  }

  const std::vector<SseEvent>& events() const { return events_; }
  int status() const { return status_; }
  const std::string& headers() const { return headers_; }
  const std::string& body() const { return body_; }
  bool closed() const { return closed_; }
  /// Microseconds since the epoch when each event was parsed (latency).
  const std::vector<int64_t>& received_us() const { return received_us_; }

 private:
  void Parse() {
    if (status_ == 0) {
      const size_t end = raw_.find("\r\n\r\n");
      if (end == std::string::npos) return;
      headers_ = raw_.substr(0, end);
      status_ = std::atoi(headers_.c_str() + headers_.find(' ') + 1);
      chunked_ = headers_.find("chunked") != std::string::npos;
      raw_.erase(0, end + 4);
    }
    if (chunked_) {
      while (true) {
        const size_t line = raw_.find("\r\n");
        if (line == std::string::npos) break;
        const size_t size = std::strtoul(raw_.c_str(), nullptr, 16);
        if (raw_.size() < line + 2 + size + 2) break;
        body_.append(raw_, line + 2, size);
        raw_.erase(0, line + 2 + size + 2);
        if (size == 0) break;
      }
    } else {
      body_ += raw_;
      raw_.clear();
    }
    size_t end;
    while ((end = body_.find("\n\n", parsed_)) != std::string::npos) {
      const std::string block = body_.substr(parsed_, end - parsed_);
      parsed_ = end + 2;
      SseEvent event{"message", "", ""};
      bool any = false;
      size_t start = 0;
      while (start <= block.size()) {
        size_t stop = block.find('\n', start);
        if (stop == std::string::npos) stop = block.size();
        const std::string line = block.substr(start, stop - start);
        if (line.rfind("event: ", 0) == 0) event.name = line.substr(7), any = true;
        if (line.rfind("data: ", 0) == 0) event.data = line.substr(6), any = true;
        if (line.rfind("id: ", 0) == 0) event.id = line.substr(4);
        start = stop + 1;
      }
      if (any) {
        events_.push_back(event);
        received_us_.push_back(std::chrono::duration_cast<std::chrono::microseconds>(
                                   std::chrono::system_clock::now().time_since_epoch())
                                   .count());
      }
    }
  }

  int fd_ = -1;
  std::string raw_;
  std::string headers_;
  std::string body_;
  size_t parsed_ = 0;
  int status_ = 0;
  bool chunked_ = false;
  bool closed_ = false;
  std::vector<SseEvent> events_;
  std::vector<int64_t> received_us_;
};

}  // namespace syrof::lab::live::testing
