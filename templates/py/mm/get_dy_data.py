{% extends "py/mm/method.py" %}
{%- block body %}
        pos_num = 0
        if {{ m.bad }}:
            status = self.BAD_ARGUMENT
        else:
            # One point per reply, until the server reports all sent (at most {{ v.point_cap }}).
            points = []
            more = True
            while more:
                status, f = self._exchange({{ m.cmd }}, [{{ m.tx }}])
                more = False
                if status != {{ m.ok }}:
                    break
                n = int(f[{{ m.lay.count_at }}]) if len(f) >= {{ m.lay.fixed }} else -1
                if n < 0 or len(f) != {{ m.lay.fixed }} + n:
                    status = self.BAD_REPLY
                    break
                if n > {{ v.user_data_len }} or len(points) >= {{ v.point_cap }}:
                    status = self.TOO_MANY_POINTS
                    break
                p = _MMPoint(f[{{ m.lay.head }} : {{ m.lay.head + 6 }}], f[{{ m.lay.label_at }}])
                p.user_data = f[{{ m.lay.fixed }} : {{ m.lay.fixed }} + n]
                points.append(p)
                more = f[{{ m.lay.all_sent_at }}] == 0
            if status == {{ m.ok }}:
                self._points, self._kind, self._pt_status = points, self.KIND_CUSTOM, status
                pos_num = len(points)
            elif points:
                # KUKA's storage was partly overwritten: nothing valid is left.
                self._points, self._kind = [], 0
        self.last_status = status
        return {{ m.ret }}
{%- endblock %}
