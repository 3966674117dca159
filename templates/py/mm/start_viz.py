{% extends "py/mm/method.py" %}
{%- block body %}
        if {{ m.bad }}:
            self.last_status = self.BAD_ARGUMENT
            return
        fields = [{{ m.tx }}]
        if sendpos_type == 1:
            fields += _mm_joints(vision_joints()) + _mm_pose(flange_pose())
        elif sendpos_type == 2:
            fields += _mm_joints(vision_joints() if mm_j is None else mm_j)
        else:
            fields += ["0"] * 6
        self.last_status, _ = self._exchange({{ m.cmd }}, fields)
{%- endblock %}
