{% extends "py/mm/method.py" %}
{%- block body %}
        if {{ m.bad }}:
            self.last_status = self.BAD_ARGUMENT
            return {{ m.none_ret }}
        p = self._point(serial, self.KIND_PLAN)
        if p is None:
            return {{ m.none_ret }}
        if self._plan_jps_pos != jps_pos:
            self.last_status = self.WRONG_DATA_KIND
            return {{ m.none_ret }}
        self._copy_data(p)
        return {{ m.value }}(*p.values), p.move_type, p.tool, p.speed
{%- endblock %}
