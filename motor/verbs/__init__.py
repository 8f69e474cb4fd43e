"""Indicating verbs (seed 001): models of a verb's hand paths and orientations as functions
of where its subject and object are placed on the arc around the signer, learned from
recordings, and their realization by the motor core."""
