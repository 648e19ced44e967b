"""The robot `urwire serve` shares between its interfaces: the arm moves only while its program
plays and it is powered, so the motion's time is the time spent moving; a stopped arm holds its
joints with zero speeds; inputs follow their masks; an input is held by one connection at a time."""
from __future__ import annotations

from urwire.live.motion import Motion
from urwire.live.robot_cell import IDLE, PAUSED, POWER_OFF, RUNNING, STOPPED, RobotCell
from urwire.live.robot_models import model_for


def cell() -> RobotCell:
    return RobotCell((5, 11, 0), model_for((5, 11, 0)))


def test_the_motion_time_is_the_time_spent_moving():
    robot = cell()
    assert robot.motion_time(5.0) == 5.0
    assert robot.stop(2.0) and robot.program_state == STOPPED
    assert (robot.motion_time(5.0), robot.motion_time(1.5)) == (2.0, 1.5)
    assert robot.play(4.0)
    assert (robot.motion_time(3.0), robot.motion_time(5.0)) == (2.0, 3.0)
    assert robot.pause(6.0) and robot.program_state == PAUSED and not robot.pause(6.5)
    assert robot.play(7.0) and robot.motion_time(8.0) == 5.0


def test_a_still_arm_holds_its_joints_with_zero_speeds():
    robot = cell()
    robot.stop(2.0)
    held = robot.joints(9.0)
    assert held.q == Motion(robot.model).joints(2.0).q
    assert set(held.qd) == set(held.qdd) == {0.0}
    state = robot.state_at(9.0)
    assert state.tcp_speed == (0.0,) * 6 and state.speed_scaling == 0.0 and state.program_state == 1


def test_toggling_the_program_keeps_few_changes_and_the_right_time():
    robot = cell()
    for i in range(1000):
        robot.stop(10.0 + i)
        robot.play(10.5 + i)
    assert len(robot._changes) <= 64
    # 10 s, then half of each of the 999 full cycles, then from the last play on.
    assert robot.motion_time(2000.0) == 10.0 + 999 * 0.5 + (2000.0 - 1009.5)


def test_power_and_play():
    robot = cell()
    robot.power(1.0, POWER_OFF)
    assert (robot.robot_mode, robot.program_state) == (POWER_OFF, STOPPED)
    assert not robot.play(2.0)                      # no program plays on an unpowered arm
    robot.power(3.0, IDLE)
    assert not robot.play(3.5) and robot.state_at(4.0).robot_mode == 5
    robot.power(5.0, RUNNING)
    assert robot.play(6.0) and robot.motion_time(7.0) == 2.0


def test_inputs_follow_their_masks_and_one_connection_holds_each():
    robot = cell()
    robot.write_inputs({"standard_digital_output_mask": 0b0110, "standard_digital_output": 0b1111})
    robot.write_inputs({"standard_digital_output_mask": 0b0010, "standard_digital_output": 0b0000})
    assert robot.digital_outputs == 0b0100
    robot.write_inputs({"speed_slider_mask": 0, "speed_slider_fraction": 0.2})
    assert robot.speed_fraction == 1.0               # bit 0 of the mask off: the slider is left alone
    robot.write_inputs({"speed_slider_mask": 1, "speed_slider_fraction": 0.2})
    assert robot.speed_fraction == 0.2
    first, second = object(), object()
    assert robot.claim_inputs(first, ["speed_slider_fraction", "input_int_register_0"]) == []
    assert robot.claim_inputs(second, ["input_int_register_0", "input_int_register_1"]) == ["input_int_register_0"]
    assert robot.claim_inputs(first, ["input_int_register_0"]) == []      # its own, again
    robot.release_inputs(first)
    assert robot.claim_inputs(second, ["input_int_register_0"]) == []
