"""The fitted models of the eight verbs (trained on the SYNTHETIC session): the GMM start,
the inflection of the paths, the two hands' relations, the citation form."""

import numpy as np
import pytest

from motor.verbs.evaluation import contact_distance
from motor.verbs.fitting import fit_session
from motor.verbs.model import MODEL_KINDS
from motor.verbs.start import best_start, path_offsets, path_score

VERBS = ("ASK", "GIVE", "MEET", "SCOLD", "TELL", "COPY", "EMAIL", "SEND")
ARRANGEMENTS = ((-0.6, 0.9), (0.9, -0.6), (-1.0, 0.0), (0.5, -1.0), (0.2, 0.4))
STEP = 0.03  # shoulder widths, about 1 cm


def test_every_verb_is_shipped_with_its_entry(models, lexicon):
    assert set(models) == set(VERBS) == set(lexicon.verbs)
    for verb, model in models.items():
        entry = lexicon.entry(verb)
        assert model.hands == entry.hands and model.keyframes == len(entry.keyframes)
        assert model.object_only == entry.object_only and model.synthetic
        assert set(entry.handshapes) == set(entry.hands) and all(entry.hamnosys.values())


@pytest.mark.parametrize("verb", VERBS)
@pytest.mark.parametrize("arrangement", ARRANGEMENTS[:3])
def test_gmm_start_lies_in_the_high_likelihood_region(models, session, verb, arrangement):
    model = models[verb]
    density = model.start_density
    steps = model.vector(*arrangement)[0][: 3 * (model.keyframes - 1)].reshape(-1, 3)
    offsets = path_offsets(steps)
    start = best_start(density, steps)
    best = path_score(density, start, offsets)[0]
    around = start + STEP * np.concatenate([np.eye(3), -np.eye(3)])
    assert np.all(path_score(density, around, offsets) <= best + 1e-9)  # a maximum
    point_start = model.predict("point", *arrangement).locations["right"][0]
    assert path_score(density, point_start, offsets)[0] <= best + 1e-9
    recorded = density.log_density(np.concatenate([p.hands["right"].location for p in session.of(verb)]))
    assert best >= np.percentile(recorded, 5)  # the path runs where 95 % of the recorded hands were as likely
    assert density.log_density(start[None])[0] >= recorded.min()  # and starts among them


@pytest.mark.parametrize("kind", ["point", "vector"])
@pytest.mark.parametrize(("subject", "obj", "toward"), [(-0.6, 0.9, -1.0), (0.9, -0.6, 1.0)])
def test_give_moves_from_the_subject_side_to_the_object_side(models, kind, subject, obj, toward):
    # +x is the signer's left: from the left (−0.6) to the right (+0.9) means x decreases
    right = models["GIVE"].predict(kind, subject, obj).locations["right"]
    assert np.sign(right[-1, 0] - right[0, 0]) == toward
    if kind == "point":
        assert np.sign(right[0, 0]) == toward * -1 and np.sign(right[-1, 0]) == toward


@pytest.mark.parametrize("arrangement", ARRANGEMENTS)
@pytest.mark.parametrize("kind", ["point", "vector"])
def test_email_passes_through_the_c_and_copy_starts_together(models, lexicon, arrangement, kind):
    for verb in ("EMAIL", "COPY"):
        entry = lexicon.entry(verb)
        gap = contact_distance(entry, lexicon, models[verb].predict(kind, *arrangement))
        assert gap * 0.36 <= entry.relation.within, (verb, gap * 36)


@pytest.mark.parametrize("verb", VERBS)
def test_uninflected_form_ignores_the_arrangement(models, verb):
    first, second = (models[verb].predict("uninflected", *a) for a in ARRANGEMENTS[:2])
    for hand in models[verb].hands:
        assert np.array_equal(first.locations[hand], second.locations[hand])
        assert np.array_equal(first.orientations[hand], second.orientations[hand])


@pytest.mark.parametrize("verb", ["SCOLD", "TELL"])
def test_object_only_verbs_ignore_the_subject(models, verb):
    one, other = models[verb].predict("point", -1.0, 0.3), models[verb].predict("point", 1.0, 0.3)
    assert np.array_equal(one.locations["right"], other.locations["right"])


@pytest.mark.parametrize("verb", VERBS)
@pytest.mark.parametrize("kind", MODEL_KINDS)
def test_predictions_are_unit_orientations_at_every_keyframe(models, verb, kind):
    form = models[verb].predict(kind, 0.3, -0.7)
    for hand in models[verb].hands:
        assert form.locations[hand].shape == (models[verb].keyframes, 3)
        assert np.allclose(np.linalg.norm(form.orientations[hand], axis=1), 1.0)
    assert np.all(np.diff(form.times) > 0)


def test_shipped_models_are_what_the_shipped_recordings_fit_to(models, session, lexicon):
    refitted = fit_session(session, lexicon).models
    for verb, model in models.items():
        for kind in ("point", "uninflected"):
            mine, shipped = refitted[verb].predict(kind, 0.1, -0.4), model.predict(kind, 0.1, -0.4)
            for hand in model.hands:
                assert np.allclose(mine.locations[hand], shipped.locations[hand], atol=1e-6)
                assert np.allclose(np.abs(np.sum(mine.orientations[hand] * shipped.orientations[hand], axis=1)), 1.0, atol=1e-6)
