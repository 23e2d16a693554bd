#!/usr/bin/python3
# The headless "display" of a LinuxCNC run on one of LinuxCNC's own kinematics modules (the
# reference side of tests/linuxcnc/run-differential): drive.py, which it imports from the same
# directory, without pkmkins' failure counters (the reference module has no such pins).
import drive

drive.counters = lambda: {}

if __name__ == "__main__":
    drive.main()
