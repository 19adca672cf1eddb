// The files of a run without a GPU (docs/command-line.md, Outputs): the claim on an output folder, input files
// that are not regular files or are too large, the checkpoints' checksums and format version, and the stats rows a
// resumed run keeps.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "Error.h"
#include "io/Checkpoint.h"
#include "io/InputFile.h"
#include "io/OutputFolder.h"
#include "io/StatsCsv.h"
#include "support/TestFiles.h"

namespace {

namespace fs = std::filesystem;
using firn::test::fileBytes;
using firn::test::freshDirectory;
using Clock = std::chrono::steady_clock;

void writeBytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

// The message of the InputError `action` throws, or "" if it throws none.
template <class Action>
std::string inputErrorOf(Action action) {
  try {
    action();
  } catch (const firn::InputError& error) {
    return error.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// ----- The claim on an output folder -----

// flock(2) locks belong to an open file description, so a second claim conflicts with the first even within one
// process: the refusal names the folder and the holder's process id. Once the first ends, its lock file is gone
// (the folder holds only outputs) and the folder is free.
TEST(OutputFolderClaim, SecondClaimIsRefusedUntilTheFirstEnds) {
  const fs::path folder = freshDirectory("claim") / "out";
  {
    const firn::OutputFolderClaim first(folder);
    EXPECT_TRUE(fs::is_directory(folder));
    const std::string message = inputErrorOf([&] { firn::OutputFolderClaim second(folder); });
    EXPECT_EQ(message, folder.string() + ": output folder in use by another firn (process " +
                           std::to_string(getpid()) + "); wait for it to end or give another --out");
  }
  EXPECT_FALSE(fs::exists(folder / firn::OutputFolderClaim::kLockFileName));
  EXPECT_EQ(inputErrorOf([&] { firn::OutputFolderClaim again(folder); }), "");
}

// A process killed with SIGKILL cannot release anything itself; the kernel drops its lock, and the lock file it
// leaves behind (naming it) is taken over by the next claim.
TEST(OutputFolderClaim, ClaimOfAKilledProcessIsTakenOver) {
  const fs::path folder = freshDirectory("killed");
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const firn::OutputFolderClaim claim(folder);
    const char byte = 1;
    if (write(ready[1], &byte, 1) != 1) _exit(1);
    pause();  // until killed
    _exit(0);
  }
  close(ready[1]);
  char byte = 0;
  ASSERT_EQ(read(ready[0], &byte, 1), 1);
  close(ready[0]);
  const fs::path lockFile = folder / firn::OutputFolderClaim::kLockFileName;
  EXPECT_TRUE(contains(inputErrorOf([&] { firn::OutputFolderClaim refused(folder); }),
                       "in use by another firn (process " + std::to_string(child) + ")"));
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(fileBytes(lockFile), std::to_string(child) + "\n") << "the killed process's lock file stays";
  {
    const firn::OutputFolderClaim takenOver(folder);
    EXPECT_EQ(fileBytes(lockFile), std::to_string(getpid()) + "\n");
  }
  EXPECT_FALSE(fs::exists(lockFile));
}

// ----- Input files -----

// A named pipe with no writer would block an open for reading, and /dev/zero never ends: both are refused from
// their stat alone, well under a second (0.5 s leaves room for a loaded machine; the refusal itself takes
// microseconds).
TEST(InputFile, PipesAndDevicesAreRefusedAtOnce) {
  const fs::path folder = freshDirectory("pipes");
  const fs::path fifo = folder / "scene.json";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  const auto start = Clock::now();
  EXPECT_EQ(inputErrorOf([&] { firn::readRegularFile(fifo, "scene file", 1 << 20); }),
            fifo.string() + ": is not a regular file but a named pipe (FIFO); a scene file is read from a regular "
                            "file only");
  EXPECT_EQ(inputErrorOf([&] { firn::readRegularFile("/dev/zero", "scene file", 1 << 20); }),
            "/dev/zero: is not a regular file but a character device; a scene file is read from a regular file only");
  EXPECT_EQ(inputErrorOf([&] { firn::readRegularFile(folder, "scene file", 1 << 20); }),
            folder.string() + ": is a folder, not a scene file");
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 0.5);
  EXPECT_EQ(inputErrorOf([&] { firn::requireRegularFile(folder / "absent", "checkpoint"); }),
            (folder / "absent").string() + ": cannot open checkpoint (No such file or directory)");
}

// A file of exactly the limit is read; one byte more is refused with both sizes.
TEST(InputFile, FilesBeyondTheLimitAreRefused) {
  const fs::path path = freshDirectory("size") / "scene.json";
  writeBytes(path, std::string(1000, ' '));
  EXPECT_EQ(firn::readRegularFile(path, "scene file", 1000).size(), 1000u);
  EXPECT_EQ(inputErrorOf([&] { firn::readRegularFile(path, "scene file", 999); }),
            path.string() + ": is 1000 bytes, more than the 999 a scene file may have");
}

// ----- Checkpoints -----

// Three buffers of distinct bytes, as a simulation's state would be.
firn::Checkpoint sampleCheckpoint() {
  firn::Checkpoint checkpoint;
  checkpoint.sceneFingerprint = 0x0123456789abcdefull;
  checkpoint.frame = 12;
  checkpoint.timeS = 0.4;
  checkpoint.steps = 4321;
  checkpoint.particleCount = 3;
  checkpoint.releasedEmitterParticles = 1;
  checkpoint.fastestSpeedMPerS = 2.5;
  for (std::size_t i = 0; i < checkpoint.energyIntegers.size(); ++i) checkpoint.energyIntegers[i] = -1000 * int(i) - 7;
  for (std::size_t i = 0; i < checkpoint.energyReals.size(); ++i) checkpoint.energyReals[i] = 0.25 * double(i) + 0.1;
  checkpoint.objectLoads = {1, -2, 3, 4, 5, -6, 7, 8};  // two objects' loads
  checkpoint.objectLoadDurationS = 0.0333;
  for (int b = 0; b < 3; ++b) {
    std::string bytes;
    for (int i = 0; i < 16 * (b + 1); ++i) bytes += char(i * 7 + b);
    checkpoint.buffers.push_back(bytes);
  }
  return checkpoint;
}

TEST(CheckpointFile, ReadsBackWhatWasWritten) {
  const fs::path path = freshDirectory("roundtrip") / "checkpoint_0012.firn";
  const firn::Checkpoint written = sampleCheckpoint();
  firn::writeCheckpoint(path, written);
  const firn::Checkpoint read = firn::readCheckpoint(path);
  EXPECT_EQ(read.sceneFingerprint, written.sceneFingerprint);
  EXPECT_EQ(read.frame, written.frame);
  EXPECT_EQ(read.timeS, written.timeS);
  EXPECT_EQ(read.steps, written.steps);
  EXPECT_EQ(read.particleCount, written.particleCount);
  EXPECT_EQ(read.releasedEmitterParticles, written.releasedEmitterParticles);
  EXPECT_EQ(read.fastestSpeedMPerS, written.fastestSpeedMPerS);
  EXPECT_EQ(read.energyIntegers, written.energyIntegers);
  EXPECT_EQ(read.energyReals, written.energyReals);
  EXPECT_EQ(read.objectLoads, written.objectLoads);
  EXPECT_EQ(read.objectLoadDurationS, written.objectLoadDurationS);
  EXPECT_EQ(read.buffers, written.buffers);
}

// CRC-32 detects every error of one byte, so no flipped byte anywhere in the file loads: each is bad input naming
// the file. A flip past the magic and the version makes the file corrupt, and in a buffer the message says which.
TEST(CheckpointFile, EveryFlippedByteIsRefusedNamingTheFile) {
  const fs::path folder = freshDirectory("flipped");
  const fs::path path = folder / "checkpoint_0012.firn";
  firn::writeCheckpoint(path, sampleCheckpoint());
  const std::string bytes = fileBytes(path);
  // As docs/command-line.md lists: to the speed estimate, the energy account (10 integers, 12 reals), the objects'
  // loads (their count, 8 of them, their duration), then the buffers' count and sizes.
  const std::size_t headerBytes = 8 + 4 + 8 + 4 + 8 + 8 + 8 + 8 + 8 + 10 * 8 + 12 * 8 + 8 + 8 * 8 + 8 + 8 + 3 * 8;
  ASSERT_EQ(bytes.size(), headerBytes + 4 + (16 + 4) + (32 + 4) + (48 + 4));
  const fs::path flipped = folder / "flipped.firn";
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    std::string damaged = bytes;
    damaged[i] = char(damaged[i] ^ 0x10);
    writeBytes(flipped, damaged);
    const std::string message = inputErrorOf([&] { firn::readCheckpoint(flipped); });
    ASSERT_EQ(message.rfind(flipped.string() + ": ", 0), 0u) << "byte " << i << " flipped: " << message;
    const char* expected = i < 8 ? ": not a Firn checkpoint" : i < 12 ? ": checkpoint format version" : ": corrupt checkpoint: ";
    EXPECT_TRUE(contains(message, expected)) << "byte " << i << " flipped: " << message;
  }
  std::string damaged = bytes;
  damaged[20] ^= 0x01;  // the frame number
  writeBytes(flipped, damaged);
  EXPECT_EQ(inputErrorOf([&] { firn::readCheckpoint(flipped); }),
            flipped.string() + ": corrupt checkpoint: the header's CRC-32 does not match its bytes (the file was "
                               "damaged or changed after it was written)");
  damaged = bytes;
  damaged[headerBytes + 4 + 20 + 5] ^= 0x01;  // a byte of the second buffer
  writeBytes(flipped, damaged);
  EXPECT_EQ(inputErrorOf([&] { firn::readCheckpoint(flipped); }),
            flipped.string() + ": corrupt checkpoint: the CRC-32 of buffer 2 of 3 does not match its bytes (the file "
                               "was damaged or changed after it was written)");
}

// Version 2 had no checksums: such a file is refused with the versions and what to do, not misread.
TEST(CheckpointFile, EarlierFormatVersionIsRefusedClearly) {
  const fs::path folder = freshDirectory("version");
  const fs::path path = folder / "checkpoint_0012.firn";
  firn::writeCheckpoint(path, sampleCheckpoint());
  std::string bytes = fileBytes(path);
  const std::uint32_t version = 2;
  std::memcpy(bytes.data() + 8, &version, sizeof version);
  writeBytes(path, bytes);
  EXPECT_EQ(inputErrorOf([&] { firn::readCheckpoint(path); }),
            path.string() + ": checkpoint format version 2, written by an earlier Firn; this build reads version 8 "
                            "only, so run the scene again from frame 0 to make new checkpoints");
}

// Cut anywhere after its header, a checkpoint is truncated; with bytes appended, corrupt.
TEST(CheckpointFile, CutOrExtendedFilesAreRefused) {
  const fs::path path = freshDirectory("cut") / "checkpoint_0012.firn";
  firn::writeCheckpoint(path, sampleCheckpoint());
  const std::string bytes = fileBytes(path);
  writeBytes(path, bytes.substr(0, bytes.size() - 1));
  EXPECT_TRUE(contains(inputErrorOf([&] { firn::readCheckpoint(path); }), ": truncated checkpoint"));
  writeBytes(path, bytes + "x");
  EXPECT_TRUE(contains(inputErrorOf([&] { firn::readCheckpoint(path); }),
                       ": corrupt checkpoint: 1 bytes follow the last buffer"));
}

// ----- stats.csv of a resumed run -----

std::string statsRow(int frame) {
  return std::to_string(frame) + ",0.1,10,100,1,0,0,0,0,5.000,0,0,0,1,0,1,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0\n";
}

// Resumed at frame 3, the file keeps the rows of frames 0 to 2 as they were, drops those of 3 on (the run writes
// them again) and a last row cut short by a killed run, and appends the new rows after the kept ones.
TEST(StatsCsvResume, KeepsTheRowsBeforeTheCheckpointsFrame) {
  const fs::path path = freshDirectory("stats") / "stats.csv";
  const std::string header = std::string(firn::StatsCsvWriter::header()) + "\n";
  writeBytes(path, header + statsRow(0) + statsRow(1) + statsRow(2) + statsRow(3) + statsRow(4) + "5,0.1,1");
  {
    firn::StatsCsvWriter stats(path, 3);
    EXPECT_EQ(fileBytes(path), header + statsRow(0) + statsRow(1) + statsRow(2));
    firn::FrameStats row;
    row.frame = 3;
    stats.write(row);
  }
  const std::string text = fileBytes(path);
  EXPECT_EQ(text.substr(0, header.size() + 3 * statsRow(0).size()), header + statsRow(0) + statsRow(1) + statsRow(2));
  EXPECT_EQ(text.substr(header.size() + 3 * statsRow(0).size(), 2), "3,");
  EXPECT_FALSE(fs::exists(path.string() + ".part"));
}

// A row without a frame number is refused naming its line, and the file is left as it was.
TEST(StatsCsvResume, ARowWithoutAFrameNumberIsRefusedNamingItsLine) {
  const fs::path path = freshDirectory("stats_bad_row") / "stats.csv";
  const std::string text = std::string(firn::StatsCsvWriter::header()) + "\n" + statsRow(0) + "x,0.1\n" + statsRow(2);
  writeBytes(path, text);
  EXPECT_EQ(inputErrorOf([&] { firn::StatsCsvWriter stats(path, 2); }),
            path.string() + ": line 3: no frame number, so the rows before frame 2 cannot be kept; move it away to "
                            "resume without them");
  EXPECT_EQ(fileBytes(path), text);
}

// Rows under another header (another version's columns) cannot be continued: refused, and the file is untouched.
TEST(StatsCsvResume, AnotherHeaderIsRefusedAndLeftAsItWas) {
  const fs::path path = freshDirectory("header") / "stats.csv";
  const std::string old = "frame,time_s,steps\n0,0,0\n1,0.1,10\n";
  writeBytes(path, old);
  EXPECT_EQ(inputErrorOf([&] { firn::StatsCsvWriter stats(path, 1); }),
            path.string() + ": its header is not the one this version of Firn writes, so its rows before frame 1 "
                            "cannot be kept; move it away to resume without them");
  EXPECT_EQ(fileBytes(path), old);
}

}  // namespace
