"""Runs `firn run SCENE --out FOLDER --mesh --vdb` as a child process and reports its progress: the rows of
stats.csv (one per frame written, frame 0 included) against the frames the run makes. Firn's own progress line
goes to a terminal only, and the frames on disk are what the import needs anyway."""

import json
import os
import subprocess
from collections import namedtuple

JobState = namedtuple("JobState", "finished exit_code fraction message")


class FirnJobError(ValueError):
    pass


def scene_frames(scene_path):
    """The frames a scene runs for (docs/scene-format.md: time.frames, default 36)."""
    with open(scene_path) as f:
        scene = json.load(f)
    return int(scene.get("time", {}).get("frames", 36))


def command(executable, scene_path, output_folder, frames=0, volume=True):
    arguments = [executable, "run", scene_path, "--out", output_folder, "--mesh"]
    if volume:
        arguments.append("--vdb")
    if frames > 0:
        arguments += ["--frames", str(frames)]
    return arguments


class FirnJob:
    def __init__(self, executable, scene_path, output_folder, frames=0, volume=True):
        if not os.path.isfile(scene_path):
            raise FirnJobError(f"{scene_path}: no such scene file")
        self.output_folder = output_folder
        self.frames = frames if frames > 0 else scene_frames(scene_path)
        os.makedirs(output_folder, exist_ok=True)
        self._log_path = os.path.join(output_folder, "firn.log")
        self._log = open(self._log_path, "w")
        try:
            self._process = subprocess.Popen(command(executable, scene_path, output_folder, frames, volume),
                                             stdout=self._log, stderr=subprocess.STDOUT)
        except FileNotFoundError:
            self._log.close()
            raise FirnJobError(f"{executable}: not found (install Firn, or set its path in the add-on's preferences)")

    def _frames_written(self):
        stats = os.path.join(self.output_folder, "stats.csv")
        if not os.path.exists(stats):
            return 0
        with open(stats) as f:
            return max(0, sum(1 for _ in f) - 1)  # less the header

    def _last_log_line(self):
        with open(self._log_path, errors="replace") as f:
            lines = [line.strip() for line in f if line.strip()]
        return lines[-1] if lines else ""

    def poll(self):
        written = self._frames_written()
        total = self.frames + 1  # frame 0, the initial state, too
        exit_code = self._process.poll()
        if exit_code is None:
            return JobState(False, None, min(written / total, 1.0), f"frame {max(written - 1, 0)} of {self.frames}")
        self._log.close()
        message = "done" if exit_code == 0 else self._last_log_line()
        return JobState(True, exit_code, 1.0, message)

    def wait(self):
        self._process.wait()
        return self.poll()

    def cancel(self):
        self._process.terminate()
        self._process.wait()
        self._log.close()
