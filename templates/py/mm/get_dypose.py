{% extends "py/mm/method.py" %}
{%- block body %}
        p = self._point(serial, self.KIND_CUSTOM)
        if p is None:
            return {{ m.none_ret }}
        self._copy_data(p)
        return Pose(*p.values), p.label
{%- endblock %}
