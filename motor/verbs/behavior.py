"""Pointing signs and indicating verbs inside utterances, timed against speech like every sign.

A behaviour whose ``spatial`` sign (:mod:`mura.space`) points at an arc position or is an
indicating verb is planned into a :class:`motor.signing.plan.SignPlan` by
:mod:`motor.verbs.plan` — the verb inflected by the model the utterance names, from the
shipped models (:mod:`motor.verbs.shipped`) unless another model file is given — and then
placed on the stroke the scheduler chose exactly as a HamNoSys sign is
(:class:`motor.signing.behavior.SignBehaviorPlanner`: a transition into its first posture,
its moves stretched onto the stroke, the retraction).
"""

from __future__ import annotations

from pathlib import Path

from motor.body.avatar import Avatar
from motor.program.fragment import PlanningError
from motor.signing.behavior import SignBehaviorPlanner
from motor.signing.plan import SignPlan, SignPlanningError
from motor.verbs.plan import pointing_plan, verb_plan
from motor.verbs.shipped import MODELS_PATH, shipped_models
from mura.errors import SpecError
from mura.model import BehaviorSpec
from mura.space import IndicatingVerbSign, SpatialSign
from mura.verb_lexicon import load_verb_lexicon


class VerbBehaviorPlanner(SignBehaviorPlanner):
    """Plans the pointing signs and indicating verbs of utterances on one avatar."""

    def __init__(self, avatar: Avatar, models: Path = MODELS_PATH) -> None:
        super().__init__(avatar)
        self.models_path = models

    def sign_plan(self, behavior: BehaviorSpec) -> SignPlan:
        """The sign's plan on its own clock; raises :class:`PlanningError` naming the behaviour."""
        spatial = behavior.spatial
        if spatial is None:
            raise PlanningError(f"behaviour {behavior.id!r} is neither a pointing sign nor an indicating verb")
        errors = (SignPlanningError, SpecError, ValueError)
        return self._remembered(spatial, lambda: spatial_plan(self.avatar, spatial, self.models_path), behavior.id, errors)

def spatial_plan(avatar: Avatar, spatial: SpatialSign, models: Path = MODELS_PATH) -> SignPlan:
    """A pointing sign or an indicating verb as a sign plan on its own clock; the verb
    inflected by the model it names, from the model file ``models``."""
    lexicon = load_verb_lexicon()
    if not isinstance(spatial, IndicatingVerbSign):
        return pointing_plan(avatar, spatial.target.arc, lexicon, spatial.gloss)
    fitted = shipped_models(models)
    if spatial.verb not in fitted:
        raise ValueError(f"{models} has no model of {spatial.verb}")
    subject = spatial.subject.arc if spatial.subject is not None else 0.0
    form = fitted[spatial.verb].predict(spatial.model, subject, spatial.object.arc)
    return verb_plan(avatar, lexicon.entry(spatial.verb), form)
