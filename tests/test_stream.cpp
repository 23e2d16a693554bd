// The grbl sender (src/pkm/stream): grbl's replies and status reports read, its error and alarm
// codes explained, the $ settings of a machine, and character counting against a fake grbl on a
// socket pair that checks its receive buffer never overflows.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "pkm/post/homing_program.hpp"
#include "pkm/stream/grbl_position.hpp"
#include "pkm/stream/grbl_replies.hpp"
#include "pkm/stream/grbl_sender.hpp"
#include "test_support.hpp"

namespace pkm::stream {
namespace {

TEST(GrblReplies, KindsAndCodes) {
  EXPECT_EQ(parse_reply("ok\r").kind, ReplyKind::ok);
  const Reply error = parse_reply("error:20");
  EXPECT_EQ(error.kind, ReplyKind::error);
  EXPECT_EQ(error.code, 20);
  const Reply alarm = parse_reply("ALARM:2\r");
  EXPECT_EQ(alarm.kind, ReplyKind::alarm);
  EXPECT_EQ(alarm.code, 2);
  EXPECT_EQ(parse_reply("Grbl 1.1h ['$' for help]").kind, ReplyKind::banner);
  EXPECT_EQ(parse_reply("[MSG:Pgm End]").kind, ReplyKind::message);
  EXPECT_EQ(parse_reply("$100=250.000").kind, ReplyKind::message);
  EXPECT_EQ(parse_reply("<Idle|MPos:0.000,0.000,0.000>").kind, ReplyKind::status);
  // Noise that looks like a reply is not one.
  EXPECT_EQ(parse_reply("error:2x").kind, ReplyKind::other);
  EXPECT_EQ(parse_reply("okay").kind, ReplyKind::other);
  EXPECT_EQ(parse_reply("\x8f\xfe~garbage").kind, ReplyKind::other);
}

TEST(GrblReplies, StatusPositionIsTheProgramsCoordinates) {
  std::array<double, 3> offset{};
  // The first report of a grbl zeroed with G10 L20 P1 X1025.914 Y1025.914 at MPos 0: WCO says so.
  auto first =
      parse_status("<Idle|MPos:0.000,0.000,0.000|FS:0,0|WCO:-1025.914,-1025.914,0.000>", offset);
  ASSERT_TRUE(first && first->has_position);
  EXPECT_EQ(first->state, "Idle");
  EXPECT_DOUBLE_EQ(first->work_position[0], 1025.914);
  EXPECT_DOUBLE_EQ(first->work_position[1], 1025.914);
  // Later reports leave WCO out: the last one seen still applies.
  auto later = parse_status("<Run|MPos:0.475,-2.5,0.000|FS:297,0|Pn:PXYZRHS>\r", offset);
  ASSERT_TRUE(later && later->has_position);
  EXPECT_EQ(later->state, "Run");
  EXPECT_DOUBLE_EQ(later->work_position[0], 0.475 + 1025.914);
  EXPECT_DOUBLE_EQ(later->work_position[1], -2.5 + 1025.914);
  // $10=0: grbl reports WPos itself.
  auto work = parse_status("<Hold:0|WPos:12.000,3.000,1.000|FS:0,0>", offset);
  ASSERT_TRUE(work);
  EXPECT_EQ(work->state, "Hold:0");
  EXPECT_DOUBLE_EQ(work->work_position[2], 1.0);
  EXPECT_FALSE(parse_status("<Idle|MPos:1,2>", offset));        // two numbers: not grbl's 3 axes
  EXPECT_FALSE(parse_status("<Idle|MPos:1,x,3>", offset));      // not a number
  EXPECT_FALSE(parse_status("Idle|MPos:1,2,3", offset));        // not a report
  EXPECT_FALSE(parse_status("<Alarm>", offset)->has_position);  // a state alone
}

TEST(GrblReplies, Meanings) {
  EXPECT_EQ(error_meaning(20), "a G or M code grbl does not support");
  EXPECT_EQ(error_meaning(9),
            "G-code is locked out while grbl is in alarm or jogging: unlock ($X) or home");
  EXPECT_EQ(error_meaning(18), "an error code grbl 1.1h does not define");
  EXPECT_EQ(alarm_meaning(3), "reset during motion: the position is probably lost, home again");
  EXPECT_EQ(alarm_meaning(10), "an alarm code grbl 1.1h does not define");
}

TEST(GrblZero, WallPlotter) {
  const machine::Machine machine = test::load_example("wall-plotter.toml");
  kinematics::JointVector joints(2);
  joints << 1025.9142, 1204.15946;
  EXPECT_EQ(post::set_position_line(machine, post::Dialect::grbl, joints),
            "G10 L20 P1 X1025.914 Y1204.159");
}

TEST(GrblPosition, ThroughForwardKinematics) {
  const machine::Machine machine = test::load_example("wall-plotter.toml");
  // Cords of 1250 mm from anchors 1500 mm apart meet 750 mm across, sqrt(1250^2 - 750^2) = 1000
  // down.
  const auto pose = tool_pose(machine, {1250.0, 1250.0, 0.0}, machine.home());
  ASSERT_TRUE(pose);
  EXPECT_NEAR(pose->position_mm.x(), 750.0, 1e-9);
  EXPECT_NEAR(pose->position_mm.y(), -1000.0, 1e-9);
  EXPECT_FALSE(tool_pose(machine, {5000.0, 5000.0, 0.0}, machine.home()));  // past the max
}

// A grbl on the other end of a socket pair: answers each line after `delay`, keeps count of the
// bytes received and not yet answered (its receive buffer), and refuses the line `refuse_line`.
struct FakeGrbl {
  int fd;
  std::chrono::milliseconds delay{1};
  int refuse_line = 0;
  int garbled_status_reports = 0;  // the first ones lose a byte as grbl-sim's once did
  bool banner = true;
  std::size_t most_buffered = 0;
  std::size_t most_buffered_with_eeprom_line = 0;  // while a $ setting or G10 was waiting
  int lines = 0;

  void run() {
    if (banner) write_text("\r\nGrbl 1.1h ['$' for help]\r\n");
    std::string pending;  // received, not yet answered
    char buffer[64];
    for (;;) {
      pollfd wait{fd, POLLIN, 0};
      if (pending.find('\n') == std::string::npos && ::poll(&wait, 1, 2000) <= 0) return;
      // Everything there is, then one answer: the sender refills the buffer in between.
      ssize_t count = 0;
      while ((count = ::recv(fd, buffer, sizeof buffer, MSG_DONTWAIT)) > 0) {
        for (ssize_t i = 0; i < count; ++i) {
          if (buffer[i] == '?' && garbled_status_reports > 0) {
            --garbled_status_reports;  // its 'P' came out as a stale line end
            write_text("<Idle|MPos:1.000,2.000,0.000|FS:0,0|\nn:PXYZRHS>\r\n");
          } else if (buffer[i] == '?') {  // real-time: answered at once, never in the buffer
            write_text("<Idle|MPos:1.000,2.000,0.000|FS:0,0>\r\n");
          } else {
            pending += buffer[i];
          }
        }
      }
      if (count == 0) return;
      most_buffered = std::max(most_buffered, pending.size());
      if (pending.find_first_of("$") != std::string::npos ||
          pending.find("G10") != std::string::npos) {
        most_buffered_with_eeprom_line = std::max(most_buffered_with_eeprom_line, pending.size());
      }
      const std::size_t end = pending.find('\n');
      if (end == std::string::npos) continue;
      std::this_thread::sleep_for(delay);
      pending.erase(0, end + 1);
      ++lines;
      write_text(lines == refuse_line ? "error:20\r\n" : "ok\r\n");
    }
  }
  void write_text(const std::string& text) const {
    // The sender may have shut its end: no SIGPIPE for that.
    if (::send(fd, text.data(), text.size(), MSG_NOSIGNAL) < 0) return;
  }
};

struct SocketPair {
  int sender = -1, grbl = -1;
  SocketPair() {
    int fds[2];
    EXPECT_EQ(::socketpair(AF_UNIX, SOCK_STREAM, 0, fds), 0);
    sender = fds[0];
    grbl = fds[1];
    ::fcntl(sender, F_SETFL, O_NONBLOCK);
  }
  ~SocketPair() {
    ::close(sender);
    ::close(grbl);
  }
};

TEST(GrblSender, CharacterCountingKeepsGrblsBufferFull) {
  SocketPair pair;
  FakeGrbl grbl{pair.grbl};
  std::thread thread([&grbl] { grbl.run(); });
  GrblSender sender(pair.sender, "fake", 128);
  sender.await_banner();
  for (int line = 1; line <= 100; ++line) {
    sender.send(
        "G1 X" + std::to_string(1000 + line) + ".12345 Y" + std::to_string(line) + ".54321 F600",
        line, 0);
    EXPECT_LE(sender.bytes_in_flight(), 128u);
  }
  sender.drain();
  ::shutdown(pair.sender, SHUT_RDWR);
  thread.join();
  EXPECT_EQ(grbl.lines, 101);  // and G4 P0
  EXPECT_EQ(sender.lines_acknowledged(), 101);
  ASSERT_TRUE(sender.last_status());
  EXPECT_EQ(sender.last_status()->state, "Idle");
  // Never more than 128 bytes waiting in grbl, and more than one line at a time (29-30 bytes
  // each): 4 lines, 117..120 bytes.
  EXPECT_LE(grbl.most_buffered, 128u);
  EXPECT_GE(grbl.most_buffered, 116u);
}

// The position at the end is asked again while no report comes whole: a report that lost a
// byte on the line is not the position (grbl-sim on a busy computer, CI of stop 33).
TEST(GrblSender, DrainAsksAgainForAGarbledStatusReport) {
  SocketPair pair;
  FakeGrbl grbl{pair.grbl};
  grbl.garbled_status_reports = 3;
  std::thread thread([&grbl] { grbl.run(); });
  GrblSender sender(pair.sender, "fake", 128);
  std::vector<std::string> messages;
  sender.on_message = [&messages](const std::string& text) { messages.push_back(text); };
  sender.await_banner();
  sender.send("G1 X1 Y2 F600", 1, 0);
  sender.drain();
  ::shutdown(pair.sender, SHUT_RDWR);
  thread.join();
  ASSERT_TRUE(sender.last_status());
  EXPECT_EQ(sender.last_status()->state, "Idle");
  EXPECT_EQ(sender.last_status()->work_position[0], 1.0);
  EXPECT_EQ(sender.last_status()->work_position[1], 2.0);
  EXPECT_EQ(grbl.garbled_status_reports, 0);
  ASSERT_GE(messages.size(), 2u);  // each garbled report's two halves, shown as what came
  EXPECT_EQ(messages[0], "<Idle|MPos:1.000,2.000,0.000|FS:0,0|");
}

// A line that writes grbl's EEPROM ($ settings, G10) goes alone: grbl holds nothing else while
// it has it, and nothing follows it before its ok.
TEST(GrblSender, EepromLinesGoAlone) {
  SocketPair pair;
  FakeGrbl grbl{pair.grbl};
  std::thread thread([&grbl] { grbl.run(); });
  GrblSender sender(pair.sender, "fake", 128);
  sender.await_banner();
  const std::string setting = "$100=80.000 (X = joint left: steps/mm)";  // 39 bytes and \n
  const std::string zero = "G10 L20 P1 X1100.000 Y950.000";              // 29 bytes and \n
  long line = 0;
  for (const std::string& special : {setting, zero}) {
    for (int i = 0; i < 10; ++i) sender.send("G1 X" + std::to_string(i) + ".5 Y2 F600", ++line, 0);
    sender.send(special, ++line, 0);
  }
  for (int i = 0; i < 10; ++i) sender.send("G1 X" + std::to_string(i) + ".5 Y2 F600", ++line, 0);
  sender.drain();
  ::shutdown(pair.sender, SHUT_RDWR);
  thread.join();
  EXPECT_EQ(grbl.lines, 33);
  EXPECT_GE(grbl.most_buffered, 100u);  // the others are streamed
  EXPECT_EQ(grbl.most_buffered_with_eeprom_line, setting.size() + 1);
  EXPECT_TRUE(stream::writes_eeprom("$100=80.000 (X = joint left: steps/mm)"));
  EXPECT_TRUE(stream::writes_eeprom("g10 l20 p1 x1"));
  EXPECT_TRUE(stream::writes_eeprom("G28.1"));
  EXPECT_TRUE(stream::writes_eeprom("$N0=G20"));
  EXPECT_FALSE(stream::writes_eeprom("$J=G91 X10 F100"));
  EXPECT_FALSE(stream::writes_eeprom("G1 X10 (G10 in a comment)"));
  EXPECT_FALSE(stream::writes_eeprom("G1 X10.5 F100"));
  EXPECT_FALSE(stream::writes_eeprom("$$"));
}

TEST(GrblSender, RefusalNamesTheLineAndItsJobLine) {
  SocketPair pair;
  FakeGrbl grbl{pair.grbl};
  grbl.refuse_line = 5;
  std::thread thread([&grbl] { grbl.run(); });
  GrblSender sender(pair.sender, "fake", 128);
  sender.await_banner();
  try {
    for (int line = 1; line <= 50; ++line)
      sender.send("G12 X" + std::to_string(line), line, 100 + line);
    sender.drain();
    FAIL() << "no refusal";
  } catch (const GrblRefusal& refusal) {
    EXPECT_EQ(refusal.line().program_line, 5);
    EXPECT_EQ(refusal.line().job_line, 105);
    EXPECT_STREQ(refusal.what(),
                 "fake: grbl refused line 5 (job line 105): G12 X5: error:20: a G or M code grbl "
                 "does not support");
  }
  ::shutdown(pair.sender, SHUT_RDWR);
  thread.join();
}

TEST(GrblSender, NoBannerIsAnErrorInBoundedTime) {
  SocketPair pair;
  const std::string noise = "\x8f\xfe~garbage\r\n";
  ASSERT_EQ(::write(pair.grbl, noise.data(), noise.size()), static_cast<ssize_t>(noise.size()));
  StreamTimeouts timeouts;
  timeouts.banner_s = 0.2;
  GrblSender sender(pair.sender, "fake", 128, timeouts);
  const auto start = std::chrono::steady_clock::now();
  try {
    sender.await_banner();
    FAIL() << "no error";
  } catch (const StreamError& error) {
    EXPECT_NE(std::string(error.what()).find("it answered \"\\x8f\\xfe~garbage\\r\\n\""),
              std::string::npos)
        << error.what();
  }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  // The sender asked for a banner with a soft reset before giving up.
  char reset = 0;
  EXPECT_EQ(::read(pair.grbl, &reset, 1), 1);
  EXPECT_EQ(reset, '\x18');
}

TEST(GrblSender, SilenceIsAnErrorNamingTheLineWaiting) {
  SocketPair pair;
  const std::string banner = "Grbl 1.1h ['$' for help]\r\n";
  ASSERT_EQ(::write(pair.grbl, banner.data(), banner.size()), static_cast<ssize_t>(banner.size()));
  StreamTimeouts timeouts;
  timeouts.silence_s = 0.3;
  GrblSender sender(pair.sender, "fake", 128, timeouts);
  sender.await_banner();
  try {
    for (int line = 1; line <= 20; ++line) sender.send("G1 X1.00000 Y2.00000 F600", line, 0);
    FAIL() << "no error";
  } catch (const StreamError& error) {
    EXPECT_NE(std::string(error.what()).find("said nothing for 0.3 s"), std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("waiting for the answer to line 1: G1 X1.00000"),
              std::string::npos)
        << error.what();
  }
}

// A grbl that sends its banner and then answers only status requests, each with `report`:
// one whose lines never come back.
std::thread status_only_grbl(int fd, std::string report) {
  return std::thread([fd, report = std::move(report) + "\r\n"] {
    const std::string banner = "Grbl 1.1h ['$' for help]\r\n";
    if (::send(fd, banner.data(), banner.size(), MSG_NOSIGNAL) < 0) return;
    char byte = 0;
    while (::recv(fd, &byte, 1, 0) == 1) {
      if (byte == '?' && ::send(fd, report.data(), report.size(), MSG_NOSIGNAL) < 0) return;
    }
  });
}

// grbl answering its status, Idle, but never the lines: it lost a newline. An error, not a hang.
TEST(GrblSender, IdleWithLinesUnansweredIsAnError) {
  SocketPair pair;
  std::thread grbl = status_only_grbl(pair.grbl, "<Idle|MPos:0.000,0.000,0.000|FS:0,0>");
  StreamTimeouts timeouts;
  timeouts.idle_stall_s = 0.5;
  GrblSender sender(pair.sender, "fake", 128, timeouts);
  sender.await_banner();
  try {
    for (int line = 1; line <= 20; ++line) sender.send("G1 X1.00000 Y2.00000 F600", line, 0);
    FAIL() << "no error";
  } catch (const StreamError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("grbl is idle, yet 4 lines sent have no answer after 0.5 s (bytes lost on "
                        "the line?), the oldest line 1: G1 X1.00000 Y2.00000 F600"),
              std::string::npos)
        << error.what();
  }
  ::shutdown(pair.sender, SHUT_RDWR);
  grbl.join();
}

// grbl answering its status, Run, at one position, and never the lines: its stepping has stopped
// (grbl-sim's clock stalls so at times on a busy computer). An error, not a hang.
TEST(GrblSender, RunWithoutMotionIsAnError) {
  SocketPair pair;
  std::thread grbl = status_only_grbl(pair.grbl, "<Run|MPos:39.525,48.350,0.000|FS:11693,0>");
  StreamTimeouts timeouts;
  timeouts.idle_stall_s = 0.5;
  GrblSender sender(pair.sender, "fake", 128, timeouts);
  sender.await_banner();
  const auto start = std::chrono::steady_clock::now();
  try {
    for (int line = 1; line <= 20; ++line) sender.send("G1 X1.00000 Y2.00000 F600", line, 0);
    FAIL() << "no error";
  } catch (const StreamError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("grbl reports Run, yet its position has stood at 39.525, 48.350, 0.000 "
                        "for 0.5 s with 4 lines unanswered: its stepping has stopped; the oldest "
                        "line waiting is line 1: G1 X1.00000 Y2.00000 F600"),
              std::string::npos)
        << error.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 3.0);
  ::shutdown(pair.sender, SHUT_RDWR);
  grbl.join();
}

}  // namespace
}  // namespace pkm::stream
