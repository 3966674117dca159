{% extends "py/mm/method.py" %}
{%- block body %}
        if not self._do_valid:
            self.last_status = self.WRONG_DATA_KIND
            return
        for n in self.do_port[1:]:
            if 1 <= n <= {{ v.out_max }}:
                kuka_out(n, True)
        self.last_status = 0
{%- endblock %}
