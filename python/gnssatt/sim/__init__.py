"""Scenario simulator."""
