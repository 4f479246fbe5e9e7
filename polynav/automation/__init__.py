"""Automation tasks: user programs (Galileo's Blockly tasks) run in a separate, limited process
that reaches the robot only through the task engine's actions."""
